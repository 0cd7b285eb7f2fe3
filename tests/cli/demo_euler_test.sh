#!/usr/bin/env bash
# `manta demo --fidelity euler --quick` end to end (docs/demo.md): the compiled-in Ranger meshed
# (full model, coarse level, sizes x 8), 26 Euler solutions of the quick campaign, the level turn
# optimised on the Euler tables, its first 2 s replayed through time-accurate Euler on the
# campaign's mesh, the report; every stage's output and run.json checked, then a second run that
# keeps every stage (no meshing, no sample, no optimisation, no replay), then an aircraft that
# cannot be meshed: the stage's one-line error, exit 2. About 3 min, then 15 s, on the 2-core
# sandbox at load 4. Usage: demo_euler_test.sh MANTA_BINARY SOURCE_DIR WORK_DIR
set -u
manta=$1
src=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
cli_show="tail -30" cli_contains_show="tail -10"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
demo=$work/demo

t0=$(date +%s)
check "euler quick demo" 0 "$manta" demo --fidelity euler --quick --out "$demo" --jobs 2
t1=$(date +%s)
echo "first run: $((t1 - t0)) s (load average $(cut -d' ' -f1-3 /proc/loadavg))"
contains "estimate printed at the start" "$work/out.txt" "estimate: about .* 26 Euler solutions"
contains "thrust scaling said" "$work/out.txt" "thrust x 3"
contains "report path" "$work/out.txt" "Report: .*/demo/report.html"
for f in report.html run.json aircraft.yaml inputs/aircraft.yaml inputs/campaign.yaml \
    inputs/cfd-euler-quick.yaml tables/mesh/aircraft_full_coarse.su2 \
    tables/mesh/aircraft_full_coarse.mesh.yaml tables/database.yaml tables/dynamic.csv \
    fly/summary.json manoeuvres/level_turn/summary.json manoeuvres/level_turn/trajectory_dense.csv \
    replay/level_turn/motion.csv replay/level_turn/comparison.csv replay/level_turn/summary.json \
    logs/tables.log logs/optimise_level_turn.log logs/replay_level_turn.log logs/report.log \
    replay/level_turn/surface/wall.csv replay/level_turn/surface/index.csv \
    replay-vlm/level_turn/motion.csv replay-vlm/level_turn/comparison.csv \
    replay-vlm/level_turn/summary.json logs/replay_vlm_level_turn.log; do
    if [ -s "$demo/$f" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: demo output $f missing"; fi
done
contains "the replay was Euler on the campaign's mesh" "$demo/logs/replay_level_turn.log" \
    "replay .*--source euler .*--mesh .*tables/mesh/aircraft_full_coarse.su2 .*--until 2"
# The lattice replay of the same 2 s beside the Euler one, and the report's sources overlay and
# surface Cp pictures (docs/demo.md, docs/report.md#surface-cp).
contains "the lattice replay against the same tables" "$demo/logs/replay_vlm_level_turn.log" \
    "replay .*--source vlm .*--tables .*tables/database.yaml .*--until 2"
contains "lattice replay summary" "$demo/replay-vlm/level_turn/summary.json" '"source": "vlm"'
contains "report: sources on the same axes" "$demo/report.html" \
    "Sources on the same axes: euler replay, table, vlm replay"
contains "report: Cp heading" "$demo/report.html" "<h3>Surface Cp</h3>"
contains "report: Cp picture" "$demo/report.html" '<svg xmlns="http://www.w3.org/2000/svg" class="cp-picture"'
if python3 - "$demo" <<'PY'
import csv, json, sys
d = sys.argv[1]
run = json.load(open(d + "/run.json"))
assert run["settings"]["fidelity"] == "euler", run["settings"]
assert run["settings"]["quick"] is True
assert run["status"] == "complete", run["status"]
assert run["euler"]["solutions"] == 26 and run["euler"]["thrust_factor"] == 3.0, run["euler"]
for k in ("tables", "fly", "optimise_total", "replay_total", "report", "total"):
    assert k in run["timings_s"], k
s = json.load(open(d + "/replay/level_turn/summary.json"))
assert s["source"] == "euler", s["source"]
# The inputs fit each other (docs/replay.md, "Bad input"): warnings of extrapolated tables only.
for w in s["input_warnings"]:
    assert w.startswith("warning: ") and "outside the tables' range" in w, w
    print(w)
assert s["snapshots"]["count"] >= 2, s["snapshots"]
v = json.load(open(d + "/replay-vlm/level_turn/summary.json"))
assert v["source"] == "vlm" and v["until"] == 2.0, (v["source"], v["until"])
assert s["until"] == 2.0 and s["steps"] == 40 and abs(s["dt"] - 0.05) < 1e-12, (s["until"], s["steps"], s["dt"])
rows = list(csv.DictReader(open(d + "/replay/level_turn/comparison.csv")))
assert len(rows) == 41 and abs(float(rows[-1]["t"]) - 2.0) < 1e-9, (len(rows), rows[-1]["t"])
# The Euler replay and the Euler tables agree at the start of a trimmed turn.
assert s["coefficients"]["CL"]["rms"] < 0.05, s["coefficients"]["CL"]
db = open(d + "/tables/database.yaml").read()
assert "euler" in db
print("replay CL rms %.4f, Cm rms %.4f over %d steps" % (s["coefficients"]["CL"]["rms"], s["coefficients"]["Cm"]["rms"], s["steps"]))
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: run.json or the replay's summary"; fi

# A second run keeps every stage.
stamp=$(stat -c %Y "$demo/tables/mesh/aircraft_full_coarse.su2")
t0=$(date +%s)
check "euler quick demo resumed" 0 "$manta" demo --fidelity euler --quick --out "$demo" --jobs 2
t1=$(date +%s)
echo "second run: $((t1 - t0)) s"
contains "optimisation kept" "$work/out.txt" "optimise level_turn: already done \(kept\)"
contains "replay kept" "$work/out.txt" "replay level_turn: already done \(kept\)"
lacks "no meshing on the rerun" "$demo/logs/tables.log" "meshing"
contains "no sample on the rerun" "$demo/logs/tables.log" "0 samples evaluated, 26 reused"
if [ "$(stat -c %Y "$demo/tables/mesh/aircraft_full_coarse.su2")" = "$stamp" ]; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: the rerun rewrote the mesh"; fi
contains "rerun complete" "$demo/run.json" '"status": "complete"'

# An aircraft that cannot be meshed (ailerons inside the fuselage): the campaign's one-line error,
# naming the copy the quick demo meshes (inputs/aircraft.yaml, its thrust scaled, same lines).
sed 's/span_fraction: \[0.55, 0.95\]/span_fraction: [0.0, 0.08]/' "$src/examples/ranger2000/aircraft.yaml" > "$work/unmeshable.yaml"
check "unmeshable aircraft" 2 "$manta" demo --fidelity euler --quick --aircraft "$work/unmeshable.yaml" --out "$work/bad"
if [ "$(wc -l < "$work/err.txt")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: not one error line"; cat "$work/err.txt"; fi
contains "names the stage, the file and the key" "$work/err.txt" "demo: the table campaign: .*bad/inputs/aircraft.yaml:[0-9]+.*control_surfaces\[1\].span_fraction"

echo "demo_euler_test: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
