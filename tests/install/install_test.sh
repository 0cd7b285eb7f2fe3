#!/usr/bin/env bash
# Usage: install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR CXX [COMPILER_LAUNCHER]
# Installs the build into WORK_DIR/prefix (`cmake --install`), checks the layout, builds
# examples/consumer against it with CMake and with g++ and pkg-config and runs both (each checks
# its optima against the published ones), then resolves every module's exported target
# (all_modules/) and .pc file, and checks that find_package(MANTA) fails, naming it, when a
# dependency is missing.
set -euo pipefail
build=$1
src=$2
work=$3
cxx=$4
launcher=${5:-}
prefix=$work/prefix
fail() {
    echo "FAIL: $*" >&2
    exit 1
}
rm -rf "$work"
mkdir -p "$work"

echo "== cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log" || fail "cmake --install (see $work/install.log)"

# the modules this build has: one .pc generated per manta_module() (cmake/MANTAInstall.cmake)
modules=()
for pc in "$build"/pkgconfig/manta-*.pc; do
    m=$(basename "$pc" .pc)
    modules+=("${m#manta-}")
done
((${#modules[@]} >= 10)) || fail "only ${#modules[@]} modules in $build/pkgconfig"
for f in bin/manta lib/cmake/MANTA/MANTAConfig.cmake lib/cmake/MANTA/MANTAConfigVersion.cmake \
    lib/cmake/MANTA/MANTATargets.cmake lib/cmake/MANTA/MANTAFindLibrary.cmake; do
    [[ -e $prefix/$f ]] || fail "$prefix/$f not installed"
done
for m in "${modules[@]}"; do
    [[ -f $prefix/lib/libmanta_$m.a ]] || fail "$prefix/lib/libmanta_$m.a not installed"
    [[ -f $prefix/lib/pkgconfig/manta-$m.pc ]] || fail "$prefix/lib/pkgconfig/manta-$m.pc not installed"
    while IFS= read -r h; do
        [[ -f $prefix/include/$h ]] || fail "header src/$m/include/$h not installed"
    done < <(cd "$src/src/$m/include" && find . -type f -name '*.hpp' | sed 's|^\./||')
done
"$prefix/bin/manta" --version >/dev/null || fail "installed manta --version"
echo "installed ${#modules[@]} modules: ${modules[*]}"

launcher_arg=()
[[ -n $launcher ]] && launcher_arg=(-DCMAKE_CXX_COMPILER_LAUNCHER="$launcher")

echo "== examples/consumer with CMake (find_package(MANTA REQUIRED COMPONENTS optimal))"
cmake -S "$src/examples/consumer" -B "$work/cmake-build" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" "${launcher_arg[@]}" \
    >"$work/cmake-configure.log" 2>&1 || { cat "$work/cmake-configure.log"; fail "consumer configure"; }
cmake --build "$work/cmake-build" >"$work/cmake-build.log" 2>&1 ||
    { cat "$work/cmake-build.log"; fail "consumer build"; }
"$work/cmake-build/consumer" || fail "consumer (CMake build) did not reach the published optima"

echo "== examples/consumer with $cxx and pkg-config (manta-optimal)"
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
flags=$(pkg-config --cflags --libs manta-optimal) || fail "pkg-config manta-optimal"
echo "pkg-config --cflags --libs manta-optimal: $flags"
# shellcheck disable=SC2086
$launcher $cxx -std=c++20 -O2 "$src/examples/consumer/main.cpp" $flags -o "$work/pc-consumer" ||
    fail "consumer with pkg-config flags"
"$work/pc-consumer" || fail "consumer (pkg-config build) did not reach the published optima"

echo "== every module: exported target and .pc file"
for m in "${modules[@]}"; do
    pkg-config --exists --print-errors "manta-$m" || fail "pkg-config manta-$m"
done
module_list=$(
    IFS=';'
    echo "${modules[*]}"
)
cmake -S "$src/tests/install/all_modules" -B "$work/all-modules" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_CXX_COMPILER="$cxx" -DMANTA_MODULES="$module_list" >"$work/all-modules.log" 2>&1 ||
    { cat "$work/all-modules.log"; fail "find_package(MANTA) with every module"; }

echo "== a missing dependency is reported"
# Eigen's package folder hidden from the search, as on a machine without Eigen
eigen_dir=$(sed -n 's/^Eigen3_DIR:PATH=//p' "$build/CMakeCache.txt")
[[ -n $eigen_dir ]] || fail "no Eigen3_DIR in $build/CMakeCache.txt"
if cmake -S "$src/examples/consumer" -B "$work/missing-dep" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_IGNORE_PATH="$eigen_dir" >"$work/missing-dep.log" 2>&1; then
    fail "find_package(MANTA) succeeded without Eigen3 (CMAKE_IGNORE_PATH=$eigen_dir)"
fi
grep -q 'Could not find a package configuration file provided by "Eigen3"' "$work/missing-dep.log" ||
    { cat "$work/missing-dep.log"; fail "the error does not name Eigen3"; }
# ... and only the requested modules' dependencies are needed: optimal needs no MPI
cmake -S "$src/examples/consumer" -B "$work/no-mpi" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON >"$work/no-mpi.log" 2>&1 ||
    { cat "$work/no-mpi.log"; fail "COMPONENTS optimal looked for MPI"; }
echo "install test passed"
