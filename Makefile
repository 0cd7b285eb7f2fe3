# MANTA — the two commands a user needs are `make demo` and `make test`.
# Every target installs missing Debian packages (scripts/install-deps.sh, idempotent) and builds.

BUILD      ?= build
BUILD_ASAN ?= build-asan
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_ARGS ?=
DEMO_OUT   ?= out/demo
FUZZ_SECONDS ?= 60

.PHONY: all deps configure build demo test validate bench test-asan format check-format clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS)

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

## Run the main job on the Ranger 2000 with the embedded default aircraft. The demo needs only the
## `manta` program: that target alone is built, so the demo starts before the tests and benchmarks
## are compiled (`make test` builds everything).
demo: configure
	cmake --build $(BUILD) -j $(JOBS) --target manta
	$(BUILD)/bin/manta demo --out $(DEMO_OUT)

## Every unit test and the fast validations against published references.
test: build
	ctest --test-dir $(BUILD) -L 'unit|validation' -LE slow --output-on-failure -j $(JOBS)

## The full validation set, slow cases included.
validate: build
	ctest --test-dir $(BUILD) -L 'validation|slow' --output-on-failure -j $(JOBS)
	bash scripts/run-fuzz.sh $(FUZZ_SECONDS)

## Benchmarks (medians of repeated runs).
bench: build
	@bash scripts/run-benchmarks.sh $(BUILD)

## Unit tests under AddressSanitizer and UndefinedBehaviorSanitizer (-O1: the lattice tests are
## minutes long at -O0). The stack is raised to 64 MiB: ASan's red zones around the second-order
## AD values of the manoeuvre derivatives (13 KiB each) overflow the default 8 MiB.
test-asan: deps
	cmake -S . -B $(BUILD_ASAN) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
	    -DMANTA_SANITIZE=ON -DMANTA_BUILD_BENCH=OFF $(CMAKE_ARGS)
	cmake --build $(BUILD_ASAN) -j $(JOBS)
	ulimit -s 65536 2>/dev/null || true; \
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	    ctest --test-dir $(BUILD_ASAN) -L 'unit|validation' -LE slow --output-on-failure -j $(JOBS)

format:
	find src tests bench -name '*.hpp' -o -name '*.cpp' | xargs clang-format -i

check-format:
	find src tests bench -name '*.hpp' -o -name '*.cpp' | xargs clang-format --dry-run --Werror

clean:
	rm -rf $(BUILD) $(BUILD_ASAN)
