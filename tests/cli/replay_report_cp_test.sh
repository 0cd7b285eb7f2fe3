#!/usr/bin/env bash
# Surface snapshots of the Euler replay and the report that draws them (docs/replay.md "Surface
# snapshots", docs/report.md "Sources on the same axes" and "Surface Cp"): on the box of
# tests/cli/replay_cli_test.sh (189 nodes, a wall floor with a flap driven by the elevator) an
# Euler replay with --snapshot-every writes surface/ (format, index, summary); kill -9 and the
# same command give the uninterrupted snapshots byte for byte; the lattice replay of the same
# trajectory in replay-vlm/ and `manta report` of the run directory show both replays and the
# table on the same axes, the differences' table and the Cp pictures.
# Usage: replay_report_cp_test.sh MANTA_BINARY REPO_ROOT WORK_DIR
set -u
manta=$1
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
ranger=$root/examples/ranger2000/aircraft.yaml

same() {  # same NAME FILE1 FILE2
    if cmp -s "$2" "$3"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: $2 and $3 differ"; fi
}

# An elevator doublet from trim (2 s), and the box mesh with its flap.
printf 't,elevator_deg\n0,0\n0.5,-2\n1,2\n1.5,0\n' > "$work/inputs.csv"
check "simulate" 0 "$manta" simulate --aircraft "$ranger" --inputs "$work/inputs.csv" --duration 2 --out "$work/traj.csv"
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
printf 'markers: {flap: wall, wall: wall, farfield: farfield}\nreference: {area: 1, chord: 1, span: 1, moment_point: [1, 0.5, 0]}\nunsteady: {max_inner: 3}\ncontrol_surfaces:\n  - {mode: elevator, marker: flap, hinge: [[1, 0.25, 0], [1, 0.75, 0]]}\n' > "$work/box.yaml"
eargs=(--trajectory "$work/traj.csv" --aircraft "$ranger" --source euler --mesh "$work/box.su2" --cfd-config "$work/box.yaml" --dt 0.01 --tolerance CL=0.02)

# 1. Snapshots every 0.25 s: steps 0, 25, ..., 200 (9 files), the index, the summary.
run=$work/run
check "euler replay with snapshots" 0 "$manta" replay "${eargs[@]}" --snapshot-every 0.25 --out "$run/replay/doublet"
contains "stdout names the snapshots" "$work/out.txt" "wrote 9 surface snapshot\(s\) every 0.25 s"
n=$(ls "$run/replay/doublet/surface" | grep -c '^step-.*\.csv$')
if [ "$n" -eq 9 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $n snapshot files, expected 9"; fi
contains "index header" "$run/replay/doublet/surface/index.csv" "^step,t,file$"
contains "index step 25" "$run/replay/doublet/surface/index.csv" "^25,0.25[0-9]*,step-000025.csv$"
contains "index last step" "$run/replay/doublet/surface/index.csv" "^200,2,step-000200.csv$"
s25=$run/replay/doublet/surface/step-000025.csv
wall=$run/replay/doublet/surface/wall.csv
contains "snapshot format line" "$s25" "^# MANTA surface snapshot 1$"
contains "snapshot names its wall" "$s25" "^# wall: wall.csv$"
contains "snapshot time" "$s25" "^# t: 0.25"
contains "snapshot nodes" "$s25" "^# nodes: 63$"
contains "snapshot header" "$s25" "^Cp$"
contains "wall format line" "$wall" "^# MANTA surface wall 1$"
contains "wall markers" "$wall" "^# markers: flap,wall$"
contains "wall nodes: the floor's 63" "$wall" "^# nodes: 63$"
contains "wall triangles: 48 quadrilaterals split" "$wall" "^# triangles: 96$"
contains "wall node header" "$wall" "^x,y,z$"
contains "wall triangle header" "$wall" "^a,b,c,marker$"
contains "summary snapshots" "$run/replay/doublet/summary.json" '"index": "surface/index.csv"'
# The floor's triangles face the flow (+z), every node lies on z = 0, one Cp per node.
if python3 - "$wall" "$s25" <<'PY'
import sys
lines = [l.strip() for l in open(sys.argv[1]) if not l.startswith("#")]
n = lines.index("a,b,c,marker")
xyz = [tuple(map(float, l.split(","))) for l in lines[1:n]]
tris = [tuple(map(int, l.split(","))) for l in lines[n + 1:]]
assert all(abs(p[2]) < 1e-12 for p in xyz)
for a, b, c, m in tris:
    (ax, ay, _), (bx, by, _), (cx, cy, _) = xyz[a], xyz[b], xyz[c]
    assert (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) > 0, "normal not into the flow"
cp = [float(l) for l in open(sys.argv[2]) if not l.startswith("#") and l.strip() != "Cp"]
assert len(cp) == len(xyz), (len(cp), len(xyz))
print(len(xyz), "nodes,", len(tris), "triangles, normals +z,", len(cp), "Cp values")
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: snapshot geometry"; fi

# 2. kill -9 after the first checkpoint, the same command: the same snapshots, byte for byte.
ekill=("${eargs[@]}" --snapshot-every 0.25 --checkpoint-steps 30)
"$manta" replay "${ekill[@]}" --out "$work/killed" >"$work/kill_out.txt" 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -f "$work/killed/checkpoint/checkpoint.json" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.02; done
if kill -9 $pid 2>/dev/null; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: the replay ended before it could be killed"; fi
wait $pid 2>/dev/null
check "euler replay after kill -9" 0 "$manta" replay "${ekill[@]}" --out "$work/killed" --json
contains "resumed from a checkpoint" "$work/out.txt" '"resumed_from_step": [1-9][0-9]*'
for f in $(ls "$run/replay/doublet/surface"); do same "resumed snapshot $f" "$run/replay/doublet/surface/$f" "$work/killed/surface/$f"; done
same "resumed comparison.csv" "$run/replay/doublet/comparison.csv" "$work/killed/comparison.csv"
# The snapshot interval is part of the checkpoint's identity.
check "keep a checkpoint" 0 "$manta" replay "${eargs[@]}" --snapshot-every 0.25 --out "$work/k2" --keep-checkpoint --checkpoint-steps 50
check "other snapshot interval refused" 2 "$manta" replay "${eargs[@]}" --snapshot-every 0.5 --out "$work/k2"
contains "refusal names the checkpoint" "$work/err.txt" "checkpoint of another replay"
# --snapshot-every 0: none; with the lattice: refused in one line.
check "no snapshots" 0 "$manta" replay "${eargs[@]}" --snapshot-every 0 --out "$work/none" --json
if [ ! -e "$work/none/surface" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --snapshot-every 0 wrote surface/"; fi
contains "summary without snapshots" "$work/none/summary.json" '"snapshots": null'
check "snapshots with the lattice" 2 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$work/bad" --snapshot-every 1
contains "lattice refusal names the option" "$work/err.txt" "snapshot-every is an option of --source euler"
one_line "lattice refusal one line" "$work/err.txt"

# 3. The lattice replay of the same trajectory beside it, and the report of the run directory.
check "vlm replay" 0 "$manta" replay --trajectory "$work/traj.csv" --aircraft "$ranger" --out "$run/replay-vlm/doublet" --n-chord 3 --strip-width 0.08 --dt 0.02 --wake-length 5 --threads 1 --tolerance CL=0.02
check "report" 0 "$manta" report "$run" --html "$work/page.html" --figures "$work/fig" --json
contains "report parts: both replays" "$work/out.txt" '"replay:traj:vlm"'
contains "report pictures" "$work/out.txt" '"pictures": [1-9]'
page=$work/page.html
contains "page: sources heading" "$page" "Sources on the same axes: euler replay, table, vlm replay"
contains "page: sources plot" "$page" 'data-figure="replay-0-sources"|"replay-0-sources"'
contains "page: euler - vlm row" "$page" "euler replay − vlm replay"
contains "page: Cp heading" "$page" "<h3>Surface Cp</h3>"
contains "page: Cp picture" "$page" '<svg xmlns="http://www.w3.org/2000/svg" class="cp-picture"'
contains "page: a reference picture" "$page" "reference"
contains "page: the snapshot time said" "$page" "the snapshot nearest"
if [ -f "$work/fig/replay-0-cp-0.svg" ] && [ -f "$work/fig/replay-0-sources.svg" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --figures wrote no Cp picture or sources figure"; ls "$work/fig"; fi
# A damaged snapshot: one line naming the file and line, no page.
cp -r "$run" "$work/badrun"
for f in "$work"/badrun/replay/doublet/surface/step-*.csv; do sed -i '16s/.*/oops/' "$f"; done
check "damaged snapshot" 2 "$manta" report "$work/badrun" --html "$work/bad.html"
contains "damaged snapshot located" "$work/err.txt" "step-[0-9]+\.csv:16: Cp 'oops' is not a number"
one_line "damaged snapshot one line" "$work/err.txt"
if [ ! -e "$work/bad.html" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: a failed report wrote a page"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
