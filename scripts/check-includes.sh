#!/usr/bin/env bash
# Fail when a module includes a module it may not depend on (docs/architecture.md; the CMake link
# lists of src/<module>/CMakeLists.txt say the same). Usage: check-includes.sh [repo-root]
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
declare -A allowed=(
  [core]=""
  [geometry]="core"
  [mesh]="core geometry"
  [meshgen]="core geometry mesh"
  [aero]="core"
  [vlm]="core geometry aero motion"
  [parallel]="core mesh"
  [euler]="core mesh aero parallel"
  [motion]="core mesh aero euler"
  [meshmotion]="core mesh aero geometry aircraft"
  [surrogate]="core"
  [optimal]="core"
  [tables]="core aero surrogate"
  [flightdyn]="core aero"
  [aircraft]="core geometry aero flightdyn"
  [manoeuvres]="core aero flightdyn optimal aircraft"
  [replay]="core aero flightdyn aircraft motion"
  [report]="*"
  [cli]="*"
)
status=0
for dir in "$root"/src/*/; do
  mod=$(basename "$dir")
  if [ -z "${allowed[$mod]+x}" ]; then
    echo "check-includes: module '$mod' is not in the dependency table of scripts/check-includes.sh"
    status=1; continue
  fi
  [ "${allowed[$mod]}" = "*" ] && continue
  while IFS= read -r line; do
    file=${line%%:*}
    inc=$(sed -E 's/.*#include +"manta\/([a-z_]+)\/.*/\1/' <<<"$line")
    [ "$inc" = "$mod" ] && continue
    if ! grep -qw -- "$inc" <<<"${allowed[$mod]}"; then
      echo "check-includes: $file includes module '$inc', which '$mod' may not depend on (allowed: ${allowed[$mod]:-none})"
      status=1
    fi
  done < <(grep -rHE '#include +"manta/[a-z_]+/' "$dir" --include='*.hpp' --include='*.cpp' | sed -E 's/^([^:]*):.*(#include.*)$/\1:\2/')
done
[ $status -eq 0 ] && echo "check-includes: all module includes follow the dependency graph"
exit $status
