#!/usr/bin/env bash
# Fuzz every input reader (docs/fuzzing.md): configure and build fuzz/ with clang into
# $BUILD_FUZZ (default build-fuzz), replay the saved regression inputs, then run each libFuzzer
# target for SECONDS (default 60): the mesh readers (su2, gmsh, cgns), the YAML readers
# (aircraft, aero_database, campaign, manoeuvre, cfd_config), the CSV readers (motion, inputs, cases,
# trajectory) and the AVL reader (avl). Fails on the first crash, sanitizer report, timeout or
# out-of-memory; the input is then under $BUILD_FUZZ/artifacts/<reader>/.
#   scripts/run-fuzz.sh [SECONDS]      e.g. scripts/run-fuzz.sh 300
#   READERS="motion avl" scripts/run-fuzz.sh 30    only these targets
# Needs clang (Debian clang-14) and libclang-rt-14-dev (it ships libclang_rt.fuzzer).
set -euo pipefail

seconds="${1:-60}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
    echo "run-fuzz.sh: SECONDS = '$seconds'; expected a positive whole number" >&2
    exit 2
fi
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_FUZZ:-$root/build-fuzz}"
jobs="${JOBS:-2}"

cxx="${FUZZ_CXX:-}"
if [ -z "$cxx" ]; then
    for c in clang++ clang++-14; do
        if command -v "$c" >/dev/null; then cxx="$c"; break; fi
    done
fi
if [ -z "$cxx" ]; then
    echo "run-fuzz.sh: clang++ not found; expected Debian clang-14 (scripts/install-deps.sh)" >&2
    exit 1
fi

cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
readers="${READERS:-su2 gmsh cgns aircraft aero_database campaign manoeuvre cfd_config motion inputs trajectory cases avl}"
targets=()
for reader in $readers; do targets+=("fuzz_$reader"); done
cmake --build "$build" -j "$jobs" --target "${targets[@]}" make_cgns_seeds

# Seeds: the files kept in fuzz/corpus/ (SU2 and MSH text; for CGNS, inputs of the decoded
# mode) and the CGNS files written now. The working corpora (what each run adds) stay in the
# build folder between runs.
case " $readers " in *" cgns "*) "$build/make_cgns_seeds" "$build/seeds/cgns" >/dev/null ;; esac
# The other readers are seeded with the examples and test data of their format as well.
seed_files() {
    case "$1" in
        aircraft) echo "$root"/examples/*/aircraft.yaml "$root"/tests/data/report/run/aircraft.yaml ;;
        campaign) echo "$root"/examples/campaigns/*.yaml "$root"/examples/ranger2000/campaign.yaml ;;
        manoeuvre) echo "$root"/examples/ranger2000/manoeuvres/*.yaml ;;
        *) ;;
    esac
}
for reader in $readers; do
    mkdir -p "$build/seeds/$reader"
    if [ -d "$root/fuzz/corpus/$reader" ]; then cp "$root"/fuzz/corpus/"$reader"/* "$build/seeds/$reader/"; fi
    for f in $(seed_files "$reader"); do
        if [ -f "$f" ]; then cp "$f" "$build/seeds/$reader/$(echo "${f#"$root"/}" | tr / _)"; fi
    done
done

status=0
for reader in $readers; do
    exe="$build/fuzz_$reader"
    corpus="$build/corpus/$reader"
    artifacts="$build/artifacts/$reader/"
    mkdir -p "$corpus" "$artifacts"
    dict=()
    if [ -f "$root/fuzz/$reader.dict" ]; then dict=(-dict="$root/fuzz/$reader.dict"); fi
    # Every saved regression input must now pass.
    regressions=("$root"/fuzz/regressions/"$reader"/*)
    if [ -e "${regressions[0]}" ]; then
        echo "== fuzz_$reader: replaying ${#regressions[@]} regression inputs"
        if ! "$exe" -runs=1 -timeout=10 "${regressions[@]}" >"$build/fuzz_$reader.replay.log" 2>&1
        then
            echo "run-fuzz.sh: fuzz_$reader fails on a saved regression input; see" \
                 "$build/fuzz_$reader.replay.log" >&2
            grep -E "Running:|ERROR|SUMMARY| in manta::|what\(\)" \
                "$build/fuzz_$reader.replay.log" | head -n 20 >&2 || true
            status=1
            continue
        fi
    fi
    echo "== fuzz_$reader: ${seconds} s"
    if ! "$exe" "${dict[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
            -print_final_stats=1 -artifact_prefix="$artifacts" \
            "$corpus" "$build/seeds/$reader" >"$build/fuzz_$reader.log" 2>&1; then
        echo "run-fuzz.sh: fuzz_$reader found a failure; input in $artifacts, log" \
             "$build/fuzz_$reader.log" >&2
        grep -E "ERROR|SUMMARY| in manta::|Test unit written|what\(\)" \
            "$build/fuzz_$reader.log" | head -n 20 >&2 || true
        status=1
        continue
    fi
    grep -E "^#[0-9]+.*DONE|stat::number_of_executed_units|stat::peak_rss_mb" \
        "$build/fuzz_$reader.log" || true
done
exit "$status"
