#!/usr/bin/env bash
# Fail when a module includes a module it may not depend on (docs/architecture.md).
# Usage: check-includes.sh [--graph] [repo-root]
#   --graph: print the graph read from the link lists instead, one line per module:
#            "<module> public: <x> ... private: <y> ..." (scripts/module-graph.sh draws it).
#
# The allowed dependencies are read from the CMake link lists, their one definition: for each
# module src/<m>/, the `manta::<x>` entries of src/<m>/CMakeLists.txt. Inside manta_module(...)
# the entries after DEPS are public (linked PUBLIC, so CMake passes them, with their include
# folders, on to every module that links <m>) and those after PRIVATE_DEPS are private (for <m>
# alone); a manta::<x> anywhere else in the file (the CLI's target_link_libraries) is private.
# Module <m> may include manta/<x>/ when <x> is <m>, one of <m>'s entries, or reachable from one
# of them through public entries: the transitive closure over DEPS, as CMake propagates it.
# Also failures: an entry naming no module under src/, a module folder without CMakeLists.txt,
# and a cycle of public entries. New modules are picked up from their folders.
set -euo pipefail
graph=0
if [ "${1:-}" = --graph ]; then graph=1; shift; fi
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
[ -d "$root/src" ] || { echo "check-includes: no src/ folder under '$root'"; exit 2; }

# The manta::<x> entries of one CMakeLists.txt as lines "public <x>" or "private <x>".
cmake_entries() {
  # Comments removed, the file as one line, then walked word by word; parentheses are counted
  # only inside manta_module( ... ) to find where its argument list ends.
  sed -e 's/#.*$//' "$1" | tr '\n\t' '  ' | awk '
    {
      text = $0; in_module = 0; depth = 0; mode = "private"; i = 1
      while (i <= length(text)) {
        rest = substr(text, i)
        if (!in_module && match(rest, /^manta_module[ ]*[(]/)) {
          in_module = 1; depth = 1; mode = "other"; i += RLENGTH; continue
        }
        c = substr(rest, 1, 1)
        if (in_module && c == "(") { depth++; i++; continue }
        if (in_module && c == ")") {
          depth--; i++
          if (depth == 0) { in_module = 0; mode = "private" }
          continue
        }
        if (match(rest, /^[A-Za-z0-9_:]+/)) {
          word = substr(rest, 1, RLENGTH); i += RLENGTH
          if (in_module && word == "DEPS") { mode = "public"; continue }
          if (in_module && word == "PRIVATE_DEPS") { mode = "private"; continue }
          if (in_module && (word == "NAME" || word == "SOURCES")) { mode = "other"; continue }
          if (mode != "other" && word ~ /^manta::[a-z_][a-z0-9_]*$/) print mode, substr(word, 8)
          continue
        }
        i++
      }
    }'
}

declare -A public_deps=() direct_deps=() known=()
status=0
for dir in "$root"/src/*/; do
  mod=$(basename "$dir")
  known[$mod]=1
done
for mod in "${!known[@]}"; do
  file="$root/src/$mod/CMakeLists.txt"
  if [ ! -f "$file" ]; then
    echo "check-includes: module '$mod' has no src/$mod/CMakeLists.txt, so no dependency list"
    status=1; continue
  fi
  public_deps[$mod]=""; direct_deps[$mod]=""
  while read -r kind dep; do
    [ -z "$dep" ] && continue
    if [ -z "${known[$dep]+x}" ]; then
      echo "check-includes: src/$mod/CMakeLists.txt links manta::$dep, which is no module under src/"
      status=1; continue
    fi
    direct_deps[$mod]+=" $dep"
    [ "$kind" = public ] && public_deps[$mod]+=" $dep"
  done < <(cmake_entries "$file")
done

if [ $graph -eq 1 ]; then
  for mod in $(printf '%s\n' "${!direct_deps[@]}" | sort); do
    priv=""
    for d in ${direct_deps[$mod]}; do
      grep -qw -- "$d" <<<"${public_deps[$mod]}" || priv+=" $d"
    done
    echo "$mod public:${public_deps[$mod]} private:$priv"
  done
  exit $status
fi

# Transitive closure over public entries (depth-first, with a cycle check).
declare -A closure=() state=()
visit() {  # visit MODULE: sets closure[MODULE] to everything MODULE's public entries reach
  local m=$1 d out=""
  if [ "${state[$m]:-}" = done ]; then return 0; fi
  if [ "${state[$m]:-}" = active ]; then
    echo "check-includes: the public dependencies (DEPS) of '$m' form a cycle"
    status=1; return 0
  fi
  state[$m]=active
  for d in ${public_deps[$m]:-}; do
    visit "$d"
    out+=" $d ${closure[$d]:-}"
  done
  closure[$m]=$(tr ' ' '\n' <<<"$out" | sort -u | tr '\n' ' ')
  state[$m]=done
}
declare -A allowed=()
for mod in $(printf '%s\n' "${!direct_deps[@]}" | sort); do
  list=""
  for d in ${direct_deps[$mod]}; do
    visit "$d"
    list+=" $d ${closure[$d]:-}"
  done
  visit "$mod"  # the cycle check for the module itself
  allowed[$mod]=$(tr ' ' '\n' <<<"$list" | sed '/^$/d' | sort -u | tr '\n' ' ')
done

for mod in $(printf '%s\n' "${!allowed[@]}" | sort); do
  dir="$root/src/$mod"
  while IFS= read -r line; do
    file=${line% *} inc=${line##* }
    [ "$inc" = "$mod" ] && continue
    if ! grep -qw -- "$inc" <<<"${allowed[$mod]}"; then
      echo "check-includes: ${file#"$root"/} includes module '$inc', which '$mod' may not depend on" \
           "(src/$mod/CMakeLists.txt allows: ${allowed[$mod]:-none})"
      status=1
    fi
  done < <( (grep -rHoE '#[[:space:]]*include[[:space:]]*[<"]manta/[a-z_][a-z0-9_]*/' "$dir" \
               --include='*.hpp' --include='*.h' --include='*.cpp' --include='*.inc' || true) |
             sed -E 's/^(.*):#.*manta\/([a-z0-9_]+)\/$/\1 \2/' | sort -u)
done
[ $status -eq 0 ] && echo "check-includes: all module includes follow the dependency graph of the CMake link lists"
exit $status
