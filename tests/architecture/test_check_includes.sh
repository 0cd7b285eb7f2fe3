#!/usr/bin/env bash
# Tests of scripts/check-includes.sh (and scripts/module-graph.sh) on small fake trees in a temporary folder: the dependency
# rules it derives from the CMake link lists (public DEPS transitive, PRIVATE_DEPS for the module
# alone), new modules picked up from their folders, and the failures it must report.
# Usage: test_check_includes.sh path/to/check-includes.sh
set -uo pipefail
check=${1:?usage: test_check_includes.sh path/to/check-includes.sh}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

# module NAME 'CMAKE TEXT' [INCLUDED_MODULE...]: src/NAME/CMakeLists.txt and one source file
# including manta/<m>/x.hpp for each m.
module() {
  local name=$1 cmake=$2; shift 2
  mkdir -p "$tree/src/$name/include/manta/$name"
  printf '%s\n' "$cmake" >"$tree/src/$name/CMakeLists.txt"
  : >"$tree/src/$name/$name.cpp"
  for m in "$@"; do printf '#include "manta/%s/x.hpp"\n' "$m" >>"$tree/src/$name/$name.cpp"; done
}

# The base tree: core <- geo <- mid (privately priv) <- top; priv <- core.
fresh() {
  tree="$work/$1"
  rm -rf "$tree"
  module core 'manta_module(NAME core SOURCES core.cpp DEPS Eigen3::Eigen)'
  module geo 'manta_module(NAME geo SOURCES geo.cpp DEPS manta::core)' core
  module priv 'manta_module(NAME priv SOURCES priv.cpp DEPS manta::core)' core
  module mid "manta_module(NAME mid
    SOURCES mid.cpp  # a comment naming manta::top is no dependency
    DEPS manta::geo
    PRIVATE_DEPS manta::priv fmt::fmt)" geo core priv
  module top 'manta_module(NAME top SOURCES ${top_sources} DEPS manta::mid Eigen3::Eigen)' mid geo core
}

# expect RC NAME [PATTERN]: run the check on $tree, compare the exit status, grep the output.
expect() {
  local rc=$1 name=$2 pattern=${3:-}
  local out got
  out=$(bash "$check" "$tree" 2>&1)
  got=$?
  if [ "$got" -ne "$rc" ]; then
    echo "FAIL $name: exit $got, expected $rc; output:"; echo "$out"
    failures=$((failures + 1)); return
  fi
  if [ -n "$pattern" ] && ! grep -qE -- "$pattern" <<<"$out"; then
    echo "FAIL $name: output lacks /$pattern/:"; echo "$out"
    failures=$((failures + 1)); return
  fi
  echo "ok   $name"
}

fresh good
expect 0 "transitive public dependencies allowed" "all module includes follow"

fresh private
printf '#include "manta/priv/x.hpp"\n' >>"$tree/src/top/top.cpp"
expect 1 "a private dependency does not propagate" "src/top/top.cpp includes module 'priv', which 'top' may not depend on"

fresh upward
printf '#include "manta/top/x.hpp"\n' >>"$tree/src/geo/include/manta/geo/x.hpp"
expect 1 "an upward include in a header" "src/geo/include/manta/geo/x.hpp includes module 'top'"

fresh angle
printf '#  include <manta/mid/x.hpp>\n' >>"$tree/src/geo/geo.cpp"
expect 1 "an angle-bracket include" "geo.cpp includes module 'mid'"

fresh comment
printf '#include "manta/top/x.hpp"\n' >>"$tree/src/mid/mid.cpp"
expect 1 "a manta:: entry in a comment is no dependency" "mid.cpp includes module 'top'"

fresh new_module
module newmod 'manta_module(NAME newmod SOURCES newmod.cpp DEPS manta::core)' core geo
expect 1 "a new module is checked against its own list" "newmod.cpp includes module 'geo'.*allows: core"
printf 'manta_module(NAME newmod SOURCES newmod.cpp\n  DEPS manta::geo)\n' >"$tree/src/newmod/CMakeLists.txt"
expect 0 "a new module's list is read when it changes"

fresh executable
module app 'add_executable(app main.cpp)
target_link_libraries(app PRIVATE manta::top manta::priv CLI11::CLI11)' top mid geo core priv
expect 0 "an executable's target_link_libraries entries"

fresh unknown
printf 'manta_module(NAME geo SOURCES geo.cpp DEPS manta::core manta::nosuch)\n' \
  >"$tree/src/geo/CMakeLists.txt"
expect 1 "an entry naming no module" "links manta::nosuch, which is no module under src/"

fresh no_cmake
mkdir -p "$tree/src/orphan"
: >"$tree/src/orphan/orphan.cpp"
expect 1 "a module folder without CMakeLists.txt" "module 'orphan' has no src/orphan/CMakeLists.txt"

fresh cycle
printf 'manta_module(NAME geo SOURCES geo.cpp DEPS manta::core manta::top)\n' \
  >"$tree/src/geo/CMakeLists.txt"
expect 1 "a cycle of public dependencies" "form a cycle"

# module-graph.sh draws the same lists: the transitive reduction, private entries dotted.
fresh graph
module app 'add_executable(app main.cpp)
target_link_libraries(app PRIVATE manta::top manta::core)'
graph_out=$(bash "$(dirname "$check")/module-graph.sh" --mermaid "$tree" 2>&1)
expected='flowchart BT
  app -.-> top
  geo --> core
  mid --> geo
  mid -.-> priv
  priv --> core
  top --> mid'
if [ "$graph_out" = "$expected" ]; then echo "ok   module-graph.sh --mermaid"; else
  echo "FAIL module-graph.sh --mermaid:"; echo "$graph_out"; failures=$((failures + 1)); fi
svg_out=$(bash "$(dirname "$check")/module-graph.sh" --svg "$tree" 2>&1)
if [ "$(grep -c '<rect x=' <<<"$svg_out")" -eq 6 ] && grep -q '</svg>' <<<"$svg_out"; then
  echo "ok   module-graph.sh --svg"; else echo "FAIL module-graph.sh --svg:"; echo "$svg_out"
  failures=$((failures + 1)); fi

# The repository's own link lists (CMakeLists.txt files only, no sources) with one wrong include
# each time: geometry may not include vlm; report reaches flightdyn through aircraft's public
# entries but not vlm; the CLI may include every module it links.
repo=$(cd "$(dirname "$check")/.." && pwd)
real() {
  tree="$work/real_$1"
  rm -rf "$tree"
  for f in "$repo"/src/*/CMakeLists.txt; do
    m=$(basename "$(dirname "$f")")
    mkdir -p "$tree/src/$m"
    cp "$f" "$tree/src/$m/"
  done
}
real geometry
printf '#include "manta/vlm/model.hpp"\n' >"$tree/src/geometry/bad.cpp"
expect 1 "repository lists: geometry including vlm" "src/geometry/bad.cpp includes module 'vlm'"
real report
printf '#include "manta/flightdyn/model.hpp"\n' >"$tree/src/report/ok.cpp"
expect 0 "repository lists: report including flightdyn (through aircraft)"
printf '#include "manta/vlm/model.hpp"\n' >"$tree/src/report/bad.cpp"
expect 1 "repository lists: report including vlm" "src/report/bad.cpp includes module 'vlm'"
real cli
for m in euler parallel mesh report replay manoeuvres optimal tables aircraft vlm; do
  printf '#include "manta/%s/x.hpp"\n' "$m" >>"$tree/src/cli/ok.cpp"
done
expect 0 "repository lists: the CLI including what it links"

if [ "$failures" -ne 0 ]; then
  echo "$failures check-includes test(s) failed"
  exit 1
fi
echo "all check-includes tests passed"
