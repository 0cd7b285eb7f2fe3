#!/usr/bin/env bash
# Robustness of the manta CLI (MANTA issue 16): command-line numbers (NaN, infinity, empty,
# out of range) rejected for every numeric option; trajectories streamed to the file; an
# unwritable --out named with its reason before any work; one command at a time in a run folder
# (the lock, its message, a stale lock taken over); temporaries of killed runs removed; control
# bytes from input files escaped in messages; the demo's stages ended with the demo; `make demo`
# building only the program. Usage: cli_robustness_test.sh MANTA_BINARY REPO_ROOT WORK_DIR
# Prints "N passed, N failed" and exits non-zero on any failure.
set -u
manta=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
ranger=$root/examples/ranger2000/aircraft.yaml
campaigns=$root/examples/campaigns
limit=${MANTA_CLI_TEST_LIMIT:-60}  # seconds one command may take (the unfixed program ran some far longer)
cli_timeout=$limit cli_show="head -8" cli_contains_show="head -5"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
lacks() {  # lacks NAME FILE PATTERN (extended regex)
    if grep -qE -- "$3" "$2"; then bad "$1: '$3' in $(basename "$2")"; sed 's/^/    /' "$2" | head -5; else ok; fi
}
no_byte() {  # no_byte NAME FILE OCTAL: the file holds no such byte
    if LC_ALL=C tr -d "\\$3" < "$2" | cmp -s - "$2"; then ok; else bad "$1: raw byte \\$3 in $(basename "$2")"; fi
}
dead() {  # dead PID: true when the process is gone (or a zombie nobody reaped)
    local state
    state=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null)
    [ -z "$state" ] || [ "$state" = Z ]
}

# Inputs: a flat-plate AVL wing, a short motion, a trajectory for replay.
printf 'Plate\n0.0\n0 0 0.0\n4.0 1.0 4.0\n0.25 0 0\nSURFACE\nWing\n4 1.0 8 1.0\nYDUPLICATE\n0.0\nSECTION\n0 0 0 1 0\nSECTION\n0 2 0 1 0\n' > "$work/plate.avl"
{ echo '# v0: 100.0'; echo 't,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder'
  for i in 0 1 2 3 4 5; do echo "0.0$i,0,0,0,0,0.05,0,0,0,0"; done; } > "$work/motion.csv"
check "trajectory for replay" 0 "$manta" simulate --aircraft "$ranger" --duration 0.5 --out "$work/traj.csv"

# ---- 8. Command-line numbers: every numeric option of every subcommand --------------------
# Each template has @ where the value goes; the rest is a valid command line.
templates=(
    "atmosphere --altitude @"
    "trim --aircraft $ranger --speed @ --altitude 3000"
    "trim --aircraft $ranger --speed 150 --altitude @"
    "trim --aircraft $ranger --speed 150 --altitude 3000 --climb-angle-deg @"
    "trim --aircraft $ranger --speed 150 --altitude 3000 --turn-rate-deg-s @"
    "trim --aircraft $ranger --speed 150 --altitude 3000 --heading-deg @"
    "modes --aircraft $ranger --speed @ --altitude 3000"
    "modes --aircraft $ranger --speed 150 --altitude @"
    "simulate --aircraft $ranger --duration @ --out $work/s8.csv"
    "simulate --aircraft $ranger --duration 1 --speed @ --out $work/s8.csv"
    "simulate --aircraft $ranger --duration 1 --altitude @ --out $work/s8.csv"
    "simulate --aircraft $ranger --duration 1 --dt @ --out $work/s8.csv"
    "simulate --aircraft $ranger --duration 1 --output-interval @ --out $work/s8.csv"
    "simulate --aircraft $ranger --duration 1 --integrator dopri5 --rtol @ --out $work/s8.csv"
    "simulate --aircraft $ranger --duration 1 --integrator dopri5 --atol @ --out $work/s8.csv"
    "vlm --aircraft $work/plate.avl --alpha-deg @"
    "vlm --aircraft $work/plate.avl --beta-deg @"
    "vlm --aircraft $work/plate.avl --mach @"
    "vlm --aircraft $work/plate.avl --p-hat @"
    "vlm --aircraft $work/plate.avl --q-hat @"
    "vlm --aircraft $work/plate.avl --r-hat @"
    "vlm --aircraft $work/plate.avl --elevator-deg @"
    "vlm --aircraft $work/plate.avl --aileron-deg @"
    "vlm --aircraft $work/plate.avl --rudder-deg @"
    "vlm --aircraft $work/plate.avl --altitude @"
    "vlm --aircraft $work/plate.avl --speed @"
    "vlm --aircraft $ranger --n-chord @ --strip-width 0.2"
    "vlm --aircraft $ranger --n-chord 2 --strip-width @"
    "vlm-unsteady --aircraft $work/plate.avl --motion $work/motion.csv --out $work/u8 --dt @"
    "vlm-unsteady --aircraft $work/plate.avl --motion $work/motion.csv --out $work/u8 --speed @"
    "vlm-unsteady --aircraft $work/plate.avl --motion $work/motion.csv --out $work/u8 --mach @"
    "vlm-unsteady --aircraft $work/plate.avl --motion $work/motion.csv --out $work/u8 --wake-length @"
    "vlm-unsteady --aircraft $ranger --motion $work/motion.csv --out $work/u8 --n-chord @"
    "vlm-unsteady --aircraft $ranger --motion $work/motion.csv --out $work/u8 --strip-width @"
    "vlm-oscillation --aircraft $work/plate.avl --k @"
    "vlm-oscillation --aircraft $work/plate.avl --amplitude-deg @"
    "vlm-oscillation --aircraft $work/plate.avl --alpha-deg @"
    "vlm-oscillation --aircraft $work/plate.avl --mach @"
    "vlm-oscillation --aircraft $work/plate.avl --periods @"
    "vlm-oscillation --aircraft $work/plate.avl --steps-per-period @"
    "vlm-oscillation --aircraft $ranger --n-chord @"
    "vlm-oscillation --aircraft $ranger --strip-width @"
    "oscillation --aircraft $work/plate.avl --k @"
    "oscillation --aircraft $work/plate.avl --periods @"
    "oscillation --aircraft $work/plate.avl --checkpoint-seconds @"
    "optimise --problem brachistochrone --nodes @"
    "optimise --problem brachistochrone --segments @"
    "optimise --problem brachistochrone --tol @"
    "optimise --problem brachistochrone --max-iter @"
    "optimise --problem brachistochrone --ipopt-print-level @"
    "tables --campaign $campaigns/analytic-small.yaml --out $work/t8 --jobs @"
    "tables --campaign $campaigns/analytic-small.yaml --out $work/t8 --progress-interval @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --dt @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --n-chord @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --strip-width @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --wake-length @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --threads @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --checkpoint-steps @"
    "replay --trajectory $work/traj.csv --aircraft $ranger --out $work/r8 --checkpoint-seconds @"
    "cfd --mesh $ranger --out $work/c8 --mach @"
    "cfd --mesh $ranger --out $work/c8 --mach 0.5 --alpha-deg @"
    "cfd --mesh $ranger --out $work/c8 --mach 0.5 --beta-deg @"
    "cfd --mesh $ranger --out $work/c8 --mach 0.5 --max-iterations @"
    "cfd --mesh $ranger --out $work/c8 --mach 0.5 --order @"
    "demo --quick --out $work/d8 --jobs @"
    "demo --quick --out $work/d8 --replay-dt @"
)
for t in "${templates[@]}"; do
    read -ra words <<< "$t"
    opt=""
    for ((i = 0; i < ${#words[@]}; ++i)); do [ "${words[i]}" = "@" ] && opt=${words[i-1]}; done
    for value in nan inf "" 12abc 1e999; do
        args=()
        for w in "${words[@]}"; do if [ "$w" = "@" ]; then args+=("$value"); else args+=("$w"); fi; done
        check "${words[0]} $opt '$value' is bad input" 2 "$manta" "${args[@]}"
        contains "${words[0]} $opt '$value': the message names the option" "$work/err.txt" "^$opt: "
        lacks "${words[0]} $opt '$value': no internal error" "$work/err.txt" "internal error"
    done
done
check "vlm --alpha-deg nan" 2 "$manta" vlm --aircraft "$work/plate.avl" --alpha-deg nan
contains "the message names value and range" "$work/err.txt" "^--alpha-deg: value 'nan' is not a finite number; expected a number in \[-90, 90\] deg"
check "atmosphere above the model" 2 "$manta" atmosphere --altitude 100000
contains "the range is named" "$work/err.txt" "outside the US Standard Atmosphere 1976 range"
check "simulate --duration 1e308" 2 "$manta" simulate --aircraft "$ranger" --duration 1e308 --out "$work/s8.csv"
contains "duration range named" "$work/err.txt" "^--duration: value '1e308' is outside the range; expected a number in \(0, 86400\] s"
check "simulate --duration 99999999999" 2 "$manta" simulate --aircraft "$ranger" --duration 99999999999 --out "$work/s8.csv"
check "vlm-unsteady --speed 99999999999" 2 "$manta" vlm-unsteady --aircraft "$work/plate.avl" --motion "$work/motion.csv" --out "$work/u8" --speed 99999999999
contains "speed range named" "$work/err.txt" "^--speed: value '99999999999' is outside the range"
check "trim --altitude ''" 2 "$manta" trim --aircraft "$ranger" --speed 150 --altitude ''
contains "empty value named" "$work/err.txt" "^--altitude: the value is empty"
mkdir -p "$work/cwd"
(cd "$work/cwd" && timeout "$limit" "$manta" tables --campaign "$campaigns/analytic-small.yaml" --out '' >"$work/out.txt" 2>"$work/err.txt"; echo $? > "$work/code.txt")
[ "$(cat "$work/code.txt")" = 2 ] && ok || bad "tables --out '': exit $(cat "$work/code.txt"), expected 2"
[ -z "$(ls -A "$work/cwd")" ] && ok || { bad "tables --out '' wrote into the current folder:"; ls -A "$work/cwd" | head -5; }
for t in "simulate --aircraft $ranger --duration 1 --out @" "simulate --aircraft $ranger --duration 1 --cases $work/none --out-dir @" \
         "cfd --mesh $ranger --mach 0.5 --out @" "vlm-unsteady --aircraft $work/plate.avl --motion $work/motion.csv --out @" \
         "optimise --problem brachistochrone --out @" "replay --trajectory $work/traj.csv --aircraft $ranger --out @" \
         "demo --quick --out @" "report $work --html @" "vlm --aircraft $work/plate.avl --vtu @"; do
    read -ra words <<< "$t"
    args=(); for w in "${words[@]}"; do if [ "$w" = "@" ]; then args+=(""); else args+=("$w"); fi; done
    check "${words[0]}: an empty path is bad input" 2 "$manta" "${args[@]}"
done
for value in nan inf 1e5; do
    check "vlm --control elevator=$value" 2 "$manta" vlm --aircraft "$ranger" --n-chord 2 --strip-width 0.2 --mach 0.3 --control "elevator=$value"
    contains "vlm --control $value named" "$work/err.txt" "^manta: error: --control: value '$value' of 'elevator' is not a deflection"
done
check "replay --tolerance CL=inf" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/r8" --tolerance CL=inf
# Values inside the ranges still work.
check "vlm in range" 0 "$manta" vlm --aircraft "$work/plate.avl" --alpha-deg +4 --mach 0 --p-hat -0.1 --json
check "trim at sea level" 0 "$manta" trim --aircraft "$ranger" --speed 150 --altitude 0

# Trajectories are streamed to the file: a long run keeps no rows in memory, and the file is
# the one the in-memory writer gives (the one-case ensemble writes through it).
# Under AddressSanitizer (MANTA_CLI_TEST_SANITIZED=1, set by tests/cli/CMakeLists.txt) the peak
# RSS measures ASan's quarantine of freed blocks, not the program: the comparison is skipped there.
if command -v /usr/bin/time >/dev/null && [ "${MANTA_CLI_TEST_SANITIZED:-0}" != 1 ]; then
    /usr/bin/time -f %M -o "$work/rss_short.txt" "$manta" simulate --aircraft "$ranger" --duration 10 --out "$work/short.csv" >/dev/null 2>&1
    /usr/bin/time -f %M -o "$work/rss_long.txt" "$manta" simulate --aircraft "$ranger" --duration 3000 --out "$work/long.csv" >/dev/null 2>&1
    short=$(tail -1 "$work/rss_short.txt"); long=$(tail -1 "$work/rss_long.txt")
    rows=$(grep -vc '^#' "$work/long.csv")
    # 300 000 rows of 26 numbers kept in memory take more than 60 MiB.
    if [ "$rows" -gt 290000 ] && [ $((long - short)) -lt 20480 ]; then ok; else
        bad "simulate 3000 s ($rows rows): peak RSS $long KiB against $short KiB for 10 s"; fi
fi
printf 'name,speed,altitude\none,150,3000\n' > "$work/one_case.csv"
check "simulate streamed" 0 "$manta" simulate --aircraft "$ranger" --duration 5 --out "$work/streamed.csv"
check "simulate one-case ensemble" 0 "$manta" simulate --aircraft "$ranger" --duration 5 --cases "$work/one_case.csv" --out-dir "$work/ens"
# The same file but for the ensemble's "# case:" line; 500 steps of 0.01 s: 501 rows and a header.
if cmp -s "$work/streamed.csv" <(grep -v '^# case: ' "$work/ens/one.csv") && [ "$(grep -vc '^#' "$work/streamed.csv")" -eq 502 ]; then ok; else
    bad "the streamed trajectory differs from the in-memory one"; diff "$work/streamed.csv" "$work/ens/one.csv" | head -5; fi
contains "streamed file keeps its metadata" "$work/streamed.csv" "^# end: completed"

# ---- 9. An unwritable --out: which path and why, exit 2, before computing -------------------
: > "$work/afile"
nodir=$work/afile/sub
for t in "cfd --mesh $ranger --mach 0.5 --out @" \
         "replay --trajectory $work/traj.csv --aircraft $ranger --out @ --dt 0.1" \
         "vlm-unsteady --aircraft $work/plate.avl --motion $work/motion.csv --out @" \
         "optimise --problem brachistochrone --nodes 10 --out @" \
         "demo --quick --out @" \
         "tables --campaign $campaigns/analytic-small.yaml --out @" \
         "simulate --aircraft $ranger --duration 1 --out @/t.csv" \
         "simulate --aircraft $ranger --duration 1 --cases $work/one_case.csv --out-dir @" \
         "report $work --html @/r.html"; do
    read -ra words <<< "$t"
    args=(); for w in "${words[@]}"; do args+=("${w//@/$nodir}"); done
    check "${words[0]} --out under a file" 2 "$manta" "${args[@]}"
    contains "${words[0]}: path and reason named" "$work/err.txt" "^manta: error: .*$nodir.*: cannot create the folder: Not a directory$"
    lacks "${words[0]}: no internal error" "$work/err.txt" "internal error"
done
check "cfd --out is a file" 2 "$manta" cfd --mesh "$ranger" --mach 0.5 --out "$work/afile"
contains "cfd: file named" "$work/err.txt" "afile: is not a folder"
if [ "$(id -u)" -ne 0 ]; then  # permissions do not bind root
    mkdir -p "$work/ro"; chmod 555 "$work/ro"
    check "optimise --out read-only" 2 "$manta" optimise --problem brachistochrone --nodes 10 --out "$work/ro/x"
    contains "read-only reason" "$work/err.txt" "ro/x.*Permission denied"
    chmod 755 "$work/ro"
fi

# ---- 2. One command at a time in a run folder ------------------------------------------------
check "tables reference run" 0 "$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/lock_ref" --jobs 2
"$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/lock" --jobs 2 >"$work/first.txt" 2>&1 &
first=$!
for _ in $(seq 100); do grep -qs since "$work/lock/.manta.lock" && break; sleep 0.05; done
check "second tables on the folder" 2 "$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/lock" --jobs 2
contains "who holds it" "$work/err.txt" "^manta: error: $work/lock is in use by manta tables \(pid $first\) since 20[0-9-]+T[0-9:]+Z"
check "cfd on the folder" 2 "$manta" cfd --mesh "$ranger" --mach 0.5 --out "$work/lock"
contains "cfd told who holds it" "$work/err.txt" "is in use by manta tables \(pid $first\)"
check "optimise on the folder" 2 "$manta" optimise --problem brachistochrone --nodes 10 --out "$work/lock"
wait "$first"; code=$?
[ "$code" -eq 0 ] && ok || { bad "first tables run: exit $code"; cat "$work/first.txt"; }
for f in tables.csv database.yaml dynamic.csv ceasiom_aero.txt; do
    cmp -s "$work/lock_ref/$f" "$work/lock/$f" && ok || bad "tables $f differs from a single run's"
done
# A lock left by a killed run is taken over.
"$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/stale" --jobs 2 >/dev/null 2>&1 &
killed=$!
for _ in $(seq 100); do grep -qs since "$work/stale/.manta.lock" && break; sleep 0.05; done
kill -9 "$killed" 2>/dev/null; wait "$killed" 2>/dev/null
check "stale lock taken over" 0 "$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/stale" --jobs 2
contains "lock file names the new holder" "$work/stale/.manta.lock" "^command tables$"

# ---- 10. Temporaries of killed runs are removed on the next run ------------------------------
mkdir -p "$work/tmp10/sub" "$work/tmp10s"
: > "$work/tmp10/samples.csv.tmp999999999"       # no such process (above any pid_max)
: > "$work/tmp10/sub/plot.svg.tmp999999998"
: > "$work/tmp10/other.csv.tmp$$"                 # this shell: alive, kept
: > "$work/tmp10s/t.csv.tmp999999997"
check "tables in a folder with leftovers" 0 "$manta" tables --campaign "$campaigns/analytic-small.yaml" --out "$work/tmp10"
[ ! -e "$work/tmp10/samples.csv.tmp999999999" ] && [ ! -e "$work/tmp10/sub/plot.svg.tmp999999998" ] && ok || bad "stale temporaries left in the run folder"
[ -e "$work/tmp10/other.csv.tmp$$" ] && ok || bad "a live process's temporary was removed"
check "simulate beside a leftover" 0 "$manta" simulate --aircraft "$ranger" --duration 1 --out "$work/tmp10s/t.csv"
[ ! -e "$work/tmp10s/t.csv.tmp999999997" ] && ok || bad "stale temporary left beside the trajectory"
ls "$work/tmp10s" | grep -q 'tmp[0-9]' && bad "simulate left a temporary: $(ls "$work/tmp10s")" || ok

# ---- 11. Control bytes from input files are escaped in messages ------------------------------
printf 't,elevator\n0,\033[31mred\n' > "$work/esc.csv"
check "ESC in an inputs file" 2 "$manta" simulate --aircraft "$ranger" --duration 1 --inputs "$work/esc.csv" --out "$work/e.csv"
no_byte "no raw ESC" "$work/err.txt" 033
contains "ESC escaped" "$work/err.txt" 'value .\\x1b\[31mred. is not a number'
printf 't,elevator\n0,1\r2\n' > "$work/cr.csv"
check "CR in an inputs file" 2 "$manta" simulate --aircraft "$ranger" --duration 1 --inputs "$work/cr.csv" --out "$work/e.csv"
no_byte "no raw CR" "$work/err.txt" 015
contains "CR escaped" "$work/err.txt" "value '1\\\\x0d2' is not a number"
printf 't,elevator\n0,1\0002\n' > "$work/nul.csv"
check "NUL in an inputs file" 2 "$manta" simulate --aircraft "$ranger" --duration 1 --inputs "$work/nul.csv" --out "$work/e.csv"
no_byte "no raw NUL" "$work/err.txt" 000
contains "NUL escaped, the message whole" "$work/err.txt" "value '1\\\\x002' is not a number"
printf 'schema_version: 1\nname: X\nref\033]0;owned\007: {}\n' > "$work/esc.yaml"
check "ESC in a YAML key" 2 "$manta" config check "$work/esc.yaml"
no_byte "no raw ESC from YAML" "$work/err.txt" 033
no_byte "no raw BEL from YAML" "$work/err.txt" 007
check "ESC on the command line" 2 "$manta" vlm --aircraft "$work/plate.avl" --alpha-deg $'\e[2J'
no_byte "no raw ESC from the command line" "$work/err.txt" 033
contains "command-line value escaped" "$work/err.txt" "value '.x1b\[2J'"
printf 't,elevator\n0,\303\251t\303\251\n' > "$work/utf8.csv"
check "UTF-8 kept" 2 "$manta" simulate --aircraft "$ranger" --duration 1 --inputs "$work/utf8.csv" --out "$work/e.csv"
contains "UTF-8 text as it is" "$work/err.txt" "value 'été' is not a number"

# ---- 13. The demo's stages end with the demo -----------------------------------------------
# SIGPIPE ignored (and so for the stages): a stage that outlives the demo is not ended by its next
# write into the demo's closed pipe, which would only hide the defect.
( trap '' PIPE; exec "$manta" demo --quick --out "$work/demo13" --jobs 1 >"$work/demo13.txt" 2>&1 ) &
demo=$!
child=""
for _ in $(seq 600); do child=$(pgrep -P "$demo" | head -1); [ -n "$child" ] && break; sleep 0.1; done
if [ -z "$child" ]; then bad "the demo started no stage in 60 s"; cat "$work/demo13.txt"; else
    ok
    kill -9 "$demo"; wait "$demo" 2>/dev/null
    for _ in $(seq 100); do dead "$child" && break; sleep 0.05; done
    dead "$child" && ok || { bad "stage $child ($(tr '\0' ' ' < "/proc/$child/cmdline")) survived kill -9 of the demo"; kill -9 "$child"; }
fi
( trap '' PIPE; exec "$manta" demo --quick --out "$work/demo13t" --jobs 1 >/dev/null 2>&1 ) &
demo=$!
child=""
for _ in $(seq 600); do child=$(pgrep -P "$demo" | head -1); [ -n "$child" ] && break; sleep 0.1; done
if [ -n "$child" ]; then
    check "second demo on the folder" 2 "$manta" demo --quick --out "$work/demo13t"
    contains "who holds the demo folder" "$work/err.txt" "demo13t is in use by manta demo \(pid $demo\)"
    kill -TERM "$demo"; wait "$demo" 2>/dev/null
    for _ in $(seq 100); do dead "$child" && break; sleep 0.05; done
    dead "$child" && ok || { bad "stage $child survived SIGTERM of the demo"; kill -9 "$child"; }
else bad "the second demo started no stage"; fi

# ---- The first command: `make demo` builds only manta before it runs ----------------------
make -n -C "$root" demo BUILD="$work/fresh" > "$work/make_demo.txt" 2>&1
contains "make demo builds the manta target" "$work/make_demo.txt" "^cmake --build $work/fresh .*--target manta$"
lacks "make demo builds nothing else" "$work/make_demo.txt" "^cmake --build [^ ]+ -j [0-9]+$"
contains "make demo then runs the demo" "$work/make_demo.txt" "^$work/fresh/bin/manta demo"
make -n -C "$root" test BUILD="$work/fresh" > "$work/make_test.txt" 2>&1
contains "make test builds everything" "$work/make_test.txt" "^cmake --build $work/fresh -j [0-9]+$"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
