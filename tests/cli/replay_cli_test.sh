#!/usr/bin/env bash
# End-to-end checks of `manta replay` (docs/replay.md): outputs, JSON, resume from a kept
# checkpoint (same comparison.csv byte for byte), mismatched checkpoint, bad input, the Euler
# source. Usage: replay_cli_test.sh MANTA_BINARY REPO_ROOT WORK_DIR
set -u
manta=$1
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
ranger=$root/examples/ranger2000/aircraft.yaml

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
check "euler source without --mesh" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/bad" --source euler
contains "euler needs --mesh" "$work/err.txt" "source euler needs --mesh FILE"
one_line "euler one line" "$work/err.txt"
check "bad tolerance" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/bad" --tolerance CQ=1
if [ ! -e "$work/bad" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: an error wrote output"; fi


# The Euler source (docs/replay.md#the-euler-source) on a box of 6 x 8 x 2 hexahedra (189 nodes)
# whose floor z = 0 is a wall with a flap (1 <= x <= 2, 0.25 <= y <= 0.75, hinge x = 1) driven by
# the elevator: outputs, the automatic time step rounded to whole steps, kill -9 and the same
# command resuming to the uninterrupted comparison.csv byte for byte, and one-line refusals.
python3 - "$work/box.su2" <<'PY'
import sys
nx, ny, nz = 6, 8, 2
def nid(i, j, k): return i + (nx + 1) * (j + (ny + 1) * k)
faces = {"flap": [], "wall": [], "farfield": []}
cells = [[nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k), nid(i, j, k + 1),
          nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
         for k in range(nz) for j in range(ny) for i in range(nx)]
for j in range(ny):  # quadrilaterals ordered for outward normals
    for i in range(nx):
        xc, yc = (i + 0.5) * 3.0 / nx, (j + 0.5) / ny
        faces["flap" if 1 <= xc <= 2 and 0.25 <= yc <= 0.75 else "wall"].append(
            [nid(i, j, 0), nid(i, j + 1, 0), nid(i + 1, j + 1, 0), nid(i + 1, j, 0)])
        faces["farfield"].append([nid(i, j, nz), nid(i + 1, j, nz), nid(i + 1, j + 1, nz), nid(i, j + 1, nz)])
for k in range(nz):
    for j in range(ny):
        faces["farfield"].append([nid(0, j, k), nid(0, j, k + 1), nid(0, j + 1, k + 1), nid(0, j + 1, k)])
        faces["farfield"].append([nid(nx, j, k), nid(nx, j + 1, k), nid(nx, j + 1, k + 1), nid(nx, j, k + 1)])
    for i in range(nx):
        faces["farfield"].append([nid(i, 0, k), nid(i + 1, 0, k), nid(i + 1, 0, k + 1), nid(i, 0, k + 1)])
        faces["farfield"].append([nid(i, ny, k), nid(i, ny, k + 1), nid(i + 1, ny, k + 1), nid(i + 1, ny, k)])
with open(sys.argv[1], "w") as f:
    f.write(f"NDIME= 3\nNELEM= {len(cells)}\n")
    for c, nodes in enumerate(cells): f.write("12 " + " ".join(map(str, nodes)) + f" {c}\n")
    f.write(f"NPOIN= {(nx + 1) * (ny + 1) * (nz + 1)}\n")
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                f.write(f"{i * 3.0 / nx!r} {j / ny!r} {k / nz!r} {nid(i, j, k)}\n")
    f.write(f"NMARK= {len(faces)}\n")
    for name, fl in faces.items():
        f.write(f"MARKER_TAG= {name}\nMARKER_ELEMS= {len(fl)}\n")
        for q in fl: f.write("9 " + " ".join(map(str, q)) + "\n")
PY
printf 'markers: {flap: wall, wall: wall, farfield: farfield}\nreference: {area: 1, chord: 1, span: 1, moment_point: [1, 0.5, 0]}\nunsteady: {max_inner: 3}\n' > "$work/box_noflap.yaml"
{ cat "$work/box_noflap.yaml"; printf 'control_surfaces:\n  - {mode: elevator, marker: flap, hinge: [[1, 0.25, 0], [1, 0.75, 0]]}\n'; } > "$work/box.yaml"
eargs=(--trajectory "$work/traj.csv" --aircraft "$ranger" --source euler --mesh "$work/box.su2" --cfd-config "$work/box.yaml")
check "replay euler" 0 "$manta" replay "${eargs[@]}" --out "$work/e1" --json
contains "euler summary source" "$work/e1/summary.json" '"source": "euler"'
contains "euler dt in whole steps" "$work/e1/summary.json" '"dt_reason": ".*rounded down to [0-9]+ whole steps'
contains "euler comparison rows" "$work/e1/comparison.csv" "^2,"
check "replay euler text" 0 "$manta" replay "${eargs[@]}" --out "$work/e2" --dt 0.01
contains "euler stdout names the nodes" "$work/out.txt" "200 steps of 0.0100 s .*through the euler source \(189 nodes\)"
contains "euler progress line" "$work/err.txt" "step 200/200"
# --cfd-start free-stream: the first row carries no load; the steady start (e2) does.
check "replay euler free-stream start" 0 "$manta" replay "${eargs[@]}" --out "$work/e3" --dt 0.01 --cfd-start free-stream
if python3 - "$work/e2/comparison.csv" "$work/e3/comparison.csv" <<'PY'
import csv, sys
steady, free = (float(next(csv.DictReader(open(f)))["CL_replay"]) for f in sys.argv[1:3])
print(f"CL at t0: steady start {steady:.4f}, free stream {free:.1e}")
assert abs(free) < 1e-12 and abs(steady) > 0.01, (steady, free)
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --cfd-start"; fi
ekill=("${eargs[@]}" --dt 0.004 --checkpoint-steps 25)
check "replay euler uninterrupted" 0 "$manta" replay "${ekill[@]}" --out "$work/efull"
"$manta" replay "${ekill[@]}" --out "$work/ekilled" >"$work/kill_out.txt" 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -f "$work/ekilled/checkpoint/checkpoint.json" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.02; done
if kill -9 $pid 2>/dev/null; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: the euler replay ended before it could be killed"; fi
wait $pid 2>/dev/null
check "replay euler after kill -9" 0 "$manta" replay "${ekill[@]}" --out "$work/ekilled" --json
contains "euler continued from a checkpoint" "$work/out.txt" '"resumed_from_step": [1-9][0-9]*'
if cmp -s "$work/efull/comparison.csv" "$work/ekilled/comparison.csv"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: euler comparison.csv after kill -9 differs from the uninterrupted run"; fi
# The elevator deflects and the configuration has no control surface for it; a time step that
# does not divide the trajectory; --mesh without --source euler.
check "euler elevator without control surface" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --source euler --mesh "$work/box.su2" --cfd-config "$work/box_noflap.yaml" --out "$work/bad"
contains "names the elevator" "$work/err.txt" "mode 'elevator' deflects"
one_line "no control surface one line" "$work/err.txt"
check "euler dt that does not divide" 2 "$manta" replay "${eargs[@]}" --out "$work/bad" --dt 0.003
contains "dt does not divide" "$work/err.txt" "time step 0.003 s does not divide the duration 2 s"
one_line "dt one line" "$work/err.txt"
check "--mesh without euler" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --mesh "$work/box.su2" --out "$work/bad"
one_line "--mesh without euler one line" "$work/err.txt"
if [ ! -e "$work/bad/comparison.csv" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: an euler error wrote output"; fi

# Bad input of the Euler replay (docs/replay.md, "Bad input"): found before the mesh is read and
# the steady start begins, one line (exit 2) naming the file, the value and what was expected,
# nothing written. Companion files beside copies of the box (the Ranger's reference values, or
# another aircraft's) and tables whose Mach range or name is another's.
companion() {  # companion FILE NAME MODEL AREA AIRCRAFT_AREA
    printf '%s\n' 'schema_version: 1' 'mesh: "box.su2"' 'aircraft: "x.yaml"' "aircraft_name: \"$2\"" \
        "model: $3" 'level: coarse' 'markers: {flap: wall, wall: wall, farfield: farfield}' \
        'reference:' "  area: $4" "  aircraft_area: $5" '  chord: 1.545' '  span: 10.46' \
        '  moment_point: [4.911169301, 0, 0.1225802693]' '  cg_case: "mtow"' '  cg: [4.9, 0, 0.12]' \
        'control_surfaces:' '  - {mode: elevator, marker: flap, hinge: [[1, 0.25, 0], [1, 0.75, 0]], gain: 1}' > "$1"
}
for d in other half same; do mkdir -p "$work/$d"; cp "$work/box.su2" "$work/$d/box.su2"; done
companion "$work/other/box.mesh.yaml" "Other jet" full 20 20
companion "$work/half/box.mesh.yaml" "Ranger 2000" half 7.75 15.5
companion "$work/same/box.mesh.yaml" "Ranger 2000" full 15.5 15.5
printf 't,aileron_deg\n0,0\n0.5,-2\n1,2\n1.5,0\n' > "$work/ail.csv"
check "simulate aileron doublet" 0 "$manta" simulate --aircraft "$ranger" --inputs "$work/ail.csv" --duration 2 --out "$work/lat.csv"
bad_input() {  # bad_input NAME PATTERN REPLAY_ARGS...: exit 2, one line matching, nothing written
    local name=$1 pattern=$2; shift 2
    rm -rf "$work/bad"
    check "$name" 2 "$manta" replay --aircraft "$ranger" --out "$work/bad" "$@"
    contains "$name: message" "$work/err.txt" "$pattern"
    one_line "$name: one line" "$work/err.txt"
    if [ ! -e "$work/bad" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $name wrote $work/bad"; fi
}
bad_input "mesh of another aircraft" \
    "other/box.su2: a mesh of the aircraft 'Other jet' \(.*other/box.mesh.yaml has reference area 20 m\^2\); expected a mesh of the aircraft file .*aircraft.yaml \('Ranger 2000': area 15.5 m\^2" \
    --source euler --trajectory "$work/traj.csv" --mesh "$work/other/box.su2"
bad_input "half model for a rolling trajectory" \
    "half/box.su2: a half model \(.*half/box.mesh.yaml: model: half\), whose symmetry plane mirrors the flow; the trajectory .*lat.csv has sideslip .* deg at t = .* s; expected a full-model mesh" \
    --source euler --trajectory "$work/lat.csv" --mesh "$work/half/box.su2"
bad_input "aileron without a control surface" \
    "lat.csv: the control mode 'aileron' deflects \(up to .* deg at t = 0.5 s\) and the default CFD configuration with the mesh companion .*same/box.mesh.yaml has no control surface of that mode \(its control surfaces: elevator\)" \
    --source euler --trajectory "$work/lat.csv" --mesh "$work/same/box.su2"
sed 's/marker: flap/marker: elev/' "$work/box.yaml" > "$work/box_elev.yaml"
bad_input "control surface on a marker the mesh lacks" \
    "box_elev.yaml:5: key 'control_surfaces\[0\]': marker 'elev' is not a marker of the mesh .*box.su2; expected one of flap, wall, farfield" \
    --source euler --trajectory "$work/traj.csv" --mesh "$work/box.su2" --cfd-config "$work/box_elev.yaml"
{ printf 'flow: {mach: 0.3}\n'; cat "$work/box.yaml"; } > "$work/box_mach.yaml"
bad_input "flow.mach other than the entry Mach" \
    "box_mach.yaml: flow.mach 0.3; the trajectory .*traj.csv enters at Mach 0.4565.*; expected no flow.mach" \
    --source euler --trajectory "$work/traj.csv" --mesh "$work/box.su2" --cfd-config "$work/box_mach.yaml"
printf 'unsteady: {max_inner: 3}\nmarkers: {flap: wall, wall: wall, farfield: farfield}\n' > "$work/box_noref.yaml"
bad_input "no reference values" \
    "box_noref.yaml: no reference values for the mesh .*box.su2 \(no .reference:. section and no mesh companion file; the solver's reference area 0 m\^2\)" \
    --source euler --trajectory "$work/traj.csv" --mesh "$work/box.su2" --cfd-config "$work/box_noref.yaml"
tab=$root/examples/ranger2000/tables-euler-half
mkdir -p "$work/tab_other/mesh"; cp "$tab/database.yaml" "$work/tab_other/"; cp "$work/other/box.mesh.yaml" "$work/tab_other/mesh/x_full_coarse.mesh.yaml"
bad_input "tables of another aircraft" \
    "tab_other: tables of the aircraft 'Other jet' \(their mesh companion .*x_full_coarse.mesh.yaml has reference area 20 m\^2\); expected tables of the aircraft file" \
    --source euler --trajectory "$work/traj.csv" --mesh "$work/same/box.su2" --tables "$work/tab_other"
sed 's/values: \[0.2, 0.3, 0.4, 0.5, 0.6\]/values: [0.7, 0.8, 0.9, 1.0, 1.1]/' "$tab/database.yaml" > "$work/db_far.yaml"
bad_input "Mach far outside the tables (euler)" \
    "traj.csv: Mach 0.455.* at t = 2 s \(.*traj.csv:[0-9]+\) is outside the tables' Mach range 0.7 to 1.1 of .*db_far.yaml by 0.24.*; expected a trajectory within 0.1" \
    --source euler --trajectory "$work/traj.csv" --mesh "$work/same/box.su2" --tables "$work/db_far.yaml"
bad_input "Mach far outside the tables (vlm)" "is outside the tables' Mach range 0.7 to 1.1" \
    --trajectory "$work/traj.csv" --tables "$work/db_far.yaml" "${coarse[@]}"
# Warnings, one line each on stderr once the replay's own checks have passed, and in summary.json:
# tables slightly beyond the trajectory's Mach, a database named for another aircraft, the box's
# own reference in its configuration.
sed -e 's/values: \[0.2, 0.3, 0.4, 0.5, 0.6\]/values: [0.5, 0.55, 0.6, 0.65, 0.7]/' \
    -e 's/name: Ranger 2000 (Euler, half model)/name: F-16 (Euler)/' "$tab/database.yaml" > "$work/db_near.yaml"
check "warnings" 0 "$manta" replay --aircraft "$ranger" --out "$work/warn" --source euler --trajectory "$work/traj.csv" --mesh "$work/box.su2" --cfd-config "$work/box.yaml" --tables "$work/db_near.yaml" --dt 0.1
contains "warning: Mach near the tables" "$work/err.txt" "^warning: .*traj.csv: Mach 0.455.* is outside the tables' Mach range 0.5 to 0.7 of .*db_near.yaml by 0.04.*; the tables are extrapolated there$"
contains "warning: another aircraft's database" "$work/err.txt" "^warning: .*db_near.yaml: the database 'F-16 \(Euler\)' does not name the aircraft 'Ranger 2000'"
contains "warning: the configuration's reference" "$work/err.txt" "^warning: .*box.yaml: reference: reference area 1 m\^2; the aircraft file .* has area 15.5 m\^2"
if [ "$(json "$work/warn/summary.json" 'len(j["input_warnings"])')" = 3 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: summary.json input_warnings"; cat "$work/warn/summary.json" | head -5; fi
# A half model for a longitudinal trajectory runs (the steady start's round-off sideslip of
# 1e-24 deg is none).
check "half model, longitudinal" 0 "$manta" replay --aircraft "$ranger" --out "$work/half_r" --source euler --trajectory "$work/traj.csv" --mesh "$work/half/box.su2" --dt 0.1
# The mesh companion of the aircraft: no warning.
check "companion of the aircraft" 0 "$manta" replay --aircraft "$ranger" --out "$work/same_r" --source euler --trajectory "$work/traj.csv" --mesh "$work/same/box.su2" --dt 0.1
lacks "no warning" "$work/err.txt" "warning"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
