#!/usr/bin/env bash
# A table campaign whose Euler source meshes the aircraft file itself (`source: {type: euler,
# aircraft: FILE, mesh: {model, level, size_factor}}`, docs/tables.md): the mesh and its companion
# written under OUT/mesh/ on the first run, reused by the rerun (no meshing, no sample evaluated),
# made again when the aircraft file changes; the one-line errors of a generated mesh without an
# aircraft, of an aircraft beside a mesh file and of an unknown level. A tiny Ranger 2000 half
# mesh (every size x 3.5), first order. Usage: tables_euler_mesh_test.sh MANTA_BINARY SOURCE_DIR
# WORK_DIR
set -u
manta=$1
src=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
cli_show="tail -20"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail

cp "$src/examples/ranger2000/aircraft.yaml" "$work/ranger.yaml"
printf '%s\n' 'numerics: {order: 1}' 'solver: {residual_drop: 3, max_iterations: 400}' > "$work/cfd.yaml"
printf '%s\n' 'schema_version: 1' 'name: ranger-euler-tiny' 'source:' '  type: euler' \
    '  aircraft: ranger.yaml' '  mesh: {model: half, level: coarse, size_factor: 3.5}' \
    '  config: cfd.yaml' 'static:' '  alpha_deg: [0, 4]' '  mach: [0.3, 0.5]' '  beta_deg: [0]' \
    '  initial_design: {size: 4, seed: 1}' '  budget: 4' > "$work/campaign.yaml"
check "campaign meshes the aircraft" 0 "$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab" --json
contains "meshing announced" "$work/err.txt" "meshing .*ranger.yaml \(half model, coarse level\)"
contains "four samples" "$work/out.txt" '"evaluated": 4'
if [ -f "$work/tab/mesh/ranger_half_coarse.su2" ] && [ -f "$work/tab/mesh/ranger_half_coarse.mesh.yaml" ]; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: no mesh and companion under OUT/mesh"; ls -R "$work/tab" | head; fi
# The lift rises with alpha on the generated mesh, with the companion's reference area.
if python3 - "$work/tab/samples.csv" <<'PY'
import csv, math, sys
r = {round(float(x["alpha_deg"])): float(x["CL"]) for x in csv.DictReader(open(sys.argv[1])) if x["status"] == "done" and abs(float(x["mach"]) - 0.3) < 1e-9}
assert set(r) == {0, 4}, r
slope = (r[4] - r[0]) / math.radians(4)
assert 3.0 < slope < 8.0, slope
print("CL_alpha", slope)
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: CL over alpha on the generated mesh"; fi
stamp_before=$(stat -c %Y "$work/tab/mesh/ranger_half_coarse.su2")
check "rerun" 0 "$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab" --json
lacks "rerun reuses the mesh" "$work/err.txt" "meshing"
contains "rerun evaluates nothing" "$work/out.txt" '"evaluated": 0'
if [ "$(stat -c %Y "$work/tab/mesh/ranger_half_coarse.su2")" = "$stamp_before" ]; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: the rerun rewrote the mesh"; fi
# A changed aircraft file is meshed again.
sed -i 's/^name: Ranger 2000$/name: Ranger 2000 changed/' "$work/ranger.yaml"
"$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab" >"$work/out.txt" 2>"$work/err.txt"
contains "changed aircraft meshed again" "$work/err.txt" "meshing"

# Bad input: a generated mesh without an aircraft, an aircraft beside a mesh file, a bad level.
sed '/^  aircraft:/d' "$work/campaign.yaml" > "$work/no_aircraft.yaml"
check "generated mesh without aircraft" 2 "$manta" tables --campaign "$work/no_aircraft.yaml" --out "$work/bad1"
one_line "generated mesh without aircraft: one line" "$work/err.txt"
contains "generated mesh without aircraft: names the key" "$work/err.txt" "no_aircraft.yaml:[0-9]+.*mesh.*source.aircraft"
sed 's|^  mesh: .*|  mesh: some.su2|' "$work/campaign.yaml" > "$work/both.yaml"
check "aircraft with a mesh file" 2 "$manta" tables --campaign "$work/both.yaml" --out "$work/bad2"
one_line "aircraft with a mesh file: one line" "$work/err.txt"
contains "aircraft with a mesh file: names the key" "$work/err.txt" "both.yaml:[0-9]+.*aircraft"
sed 's|level: coarse|level: huge|' "$work/campaign.yaml" > "$work/level.yaml"
check "unknown level" 2 "$manta" tables --campaign "$work/level.yaml" --out "$work/bad3"
one_line "unknown level: one line" "$work/err.txt"
contains "unknown level: lists the choices" "$work/err.txt" "coarse.*medium.*fine"

# An elevator table beyond the aircraft file's limits (-25..15 deg): refused before the mesh is built.
cp "$work/campaign.yaml" "$work/limits.yaml"
printf '%s\n' 'controls:' '  elevator: {deflection_deg: [-30, 0, 10], samples: 2}' >> "$work/limits.yaml"
check "elevator beyond the aircraft's limits" 2 "$manta" tables --campaign "$work/limits.yaml" --out "$work/bad4"
one_line "elevator beyond the limits: one line" "$work/err.txt"
contains "elevator beyond the limits: names the key" "$work/err.txt" "limits.yaml:[0-9]+.*controls.elevator.deflection_deg"
if [ ! -e "$work/bad4/mesh" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: meshed before refusing the limits"; fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
