#!/usr/bin/env bash
# End-to-end checks of `manta replay` (docs/replay.md): outputs, JSON, resume from a kept
# checkpoint (same comparison.csv byte for byte), mismatched checkpoint, bad input, the Euler
# source. Usage: replay_cli_test.sh MANTA_BINARY REPO_ROOT WORK_DIR
set -u
manta=$1
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
pass=0; fail=0
ranger=$root/examples/ranger2000/aircraft.yaml

check() {  # check NAME EXPECTED_EXIT COMMAND...
    local name=$1 expected=$2; shift 2
    "$@" >"$work/out.txt" 2>"$work/err.txt"
    local code=$?
    if [ "$code" -eq "$expected" ]; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAIL: $name: exit $code, expected $expected"
        sed 's/^/    /' "$work/out.txt" "$work/err.txt" | head -20
    fi
}
contains() {  # contains NAME FILE PATTERN
    if grep -qE -- "$3" "$2"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: '$3' not in $(basename "$2")"; sed 's/^/    /' "$2" | head -10; fi
}
one_line() {  # one_line NAME FILE: exactly one line
    if [ "$(wc -l < "$2")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: not one line"; cat "$2"; fi
}
coarse=(--n-chord 3 --strip-width 0.08 --dt 0.05 --wake-length 5)

check "replay --help" 0 "$manta" replay --help
contains "help names --trajectory" "$work/out.txt" "--trajectory"
contains "help names --tables" "$work/out.txt" "--tables"

# A trajectory from the simulator: an elevator doublet from trim.
printf 't,elevator_deg\n0,0\n0.5,-2\n1,2\n1.5,0\n' > "$work/inputs.csv"
check "simulate" 0 "$manta" simulate --aircraft "$ranger" --inputs "$work/inputs.csv" --duration 2 --out "$work/traj.csv"

check "replay" 0 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/r1" "${coarse[@]}" --keep-checkpoint --checkpoint-steps 10 --tolerance CL=0.5
for f in motion.csv comparison.csv summary.json checkpoint/checkpoint.json; do
    if [ -f "$work/r1/$f" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: replay wrote no $f"; fi
done
contains "comparison header" "$work/r1/comparison.csv" "^t,phase,alpha,beta,V,mach,p,q,r,elevator,aileron,rudder,elevator_rate,aileron_rate,rudder_rate,CL_replay,CL_table,CL_diff"
contains "motion metadata" "$work/r1/motion.csv" "^# v0: "
contains "summary tolerance override" "$work/r1/summary.json" '"CL": 0.5'
contains "stdout table" "$work/out.txt" "^CL "

# The kept checkpoint (step 30 of 40): the same command resumes from it to the same result.
cp "$work/r1/comparison.csv" "$work/first.csv"
check "replay resumed" 0 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/r1" "${coarse[@]}" --checkpoint-steps 10 --tolerance CL=0.5 --json
contains "resumed from the checkpoint" "$work/out.txt" '"resumed_from_step": 30'
if cmp -s "$work/first.csv" "$work/r1/comparison.csv"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: resumed comparison.csv differs"; fi
if [ ! -d "$work/r1/checkpoint" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: checkpoint left behind"; fi

# A checkpoint of other settings: clear error, then --restart.
check "replay keep" 0 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/r2" "${coarse[@]}" --keep-checkpoint --checkpoint-steps 10
check "replay mismatched checkpoint" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/r2" --n-chord 3 --strip-width 0.08 --dt 0.04 --wake-length 5
contains "mismatch says --restart" "$work/err.txt" "checkpoint of another replay.*--restart"
one_line "mismatch one line" "$work/err.txt"
check "replay --restart" 0 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/r2" --n-chord 3 --strip-width 0.08 --dt 0.04 --wake-length 5 --restart --json
contains "restart did not resume" "$work/out.txt" '"resumed_from_step": null'

# kill -9 during a replay, then the same command: it continues from the last checkpoint and
# writes the same comparison.csv as an uninterrupted run, byte for byte.
check "simulate long" 0 "$manta" simulate --aircraft "$ranger" --inputs "$work/inputs.csv" --duration 20 --out "$work/long.csv"
killargs=(--trajectory "$work/long.csv" --aircraft "$ranger" --n-chord 3 --strip-width 0.08 --dt 0.005 --wake-length 5 --checkpoint-steps 200 --threads 1)
check "replay uninterrupted" 0 "$manta" replay "${killargs[@]}" --out "$work/full"
"$manta" replay "${killargs[@]}" --out "$work/killed" >"$work/kill_out.txt" 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -f "$work/killed/checkpoint/checkpoint.json" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.02; done
if kill -9 $pid 2>/dev/null; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: the replay ended before it could be killed"; fi
wait $pid 2>/dev/null
if [ ! -f "$work/killed/comparison.csv" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: a killed replay left a comparison.csv"; fi
check "replay after kill -9" 0 "$manta" replay "${killargs[@]}" --out "$work/killed" --json
contains "continued from a checkpoint" "$work/out.txt" '"resumed_from_step": [1-9][0-9]*'
if cmp -s "$work/full/comparison.csv" "$work/killed/comparison.csv"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: comparison.csv after kill -9 differs from the uninterrupted run"; fi

# Bad input: one line naming file, line and column; nothing written.
h=$(grep -n '^t,' "$work/traj.csv" | cut -d: -f1)  # header line (metadata lines come first)
head -n $((h + 1)) "$work/traj.csv" > "$work/bad.csv"
sed -n "$((h + 1))p" "$work/traj.csv" >> "$work/bad.csv"
check "duplicated time" 2 "$manta" replay --trajectory "$work/bad.csv" --aircraft "$ranger" --out "$work/bad"
contains "duplicated time located" "$work/err.txt" "bad.csv:$((h + 2)), column 1 't'"
one_line "duplicated time one line" "$work/err.txt"
if [ ! -e "$work/bad" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: bad input wrote output"; fi
awk -F, -v row=$((h + 3)) 'BEGIN{OFS=","} NR==row{$9="nan"} {print}' "$work/traj.csv" > "$work/nan.csv"
check "NaN alpha" 2 "$manta" replay --trajectory "$work/nan.csv" --aircraft "$ranger" --out "$work/bad"
contains "NaN located" "$work/err.txt" "nan.csv:$((h + 3)), column 9 'alpha': nan"
awk -F, -v row=$((h + 3)) 'BEGIN{OFS=","} NR==row{$6="2.0"} {print}' "$work/traj.csv" > "$work/theta.csv"
check "theta out of range" 2 "$manta" replay --trajectory "$work/theta.csv" --aircraft "$ranger" --out "$work/bad"
contains "theta located" "$work/err.txt" "theta.csv:$((h + 3)), column 6 'theta'"
cut -d, -f1-8 "$work/traj.csv" > "$work/short.csv"
check "missing columns" 2 "$manta" replay --trajectory "$work/short.csv" --aircraft "$ranger" --out "$work/bad"
contains "missing columns named" "$work/err.txt" "missing column\(s\) alpha, beta, p, q, r, elevator, aileron, rudder"
check "euler source" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/bad" --source euler
contains "euler cannot replay" "$work/err.txt" "Euler source cannot replay yet"
one_line "euler one line" "$work/err.txt"
check "bad tolerance" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/bad" --tolerance CQ=1
if [ ! -e "$work/bad" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: an error wrote output"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
