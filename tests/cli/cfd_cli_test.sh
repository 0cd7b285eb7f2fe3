#!/usr/bin/env bash
# End-to-end checks of `manta cfd` (docs/euler.md) on the coarse ONERA M6 mesh: help, JSON
# output and files, a run continued from its restart file, a foreign restart file, bad input
# (one-line errors, exit 2), and 1 versus 2 MPI processes giving the same converged
# coefficients. Usage: cfd_cli_test.sh MANTA_BINARY SHARED_DIR WORK_DIR [MPIEXEC]
set -u
manta=$1
shared=$2
work=$3
mpiexec=${4:-}
mpiflags=()
if [ -n "$mpiexec" ] && "$mpiexec" --version 2>&1 | grep -qiE "open ?mpi|openrte"; then
    mpiflags=(--oversubscribe --allow-run-as-root)
fi
rm -rf "$work"; mkdir -p "$work"
cli_show="tail -20"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
mesh=$shared/reference/onera_m6/mesh_ONERAM6_inv_gmsh_coarse.su2.gz
if [ ! -f "$mesh" ]; then echo "SKIP: $mesh not found"; exit 77; fi


check "cfd --help" 0 "$manta" cfd --help
contains "help names --mesh" "$work/out.txt" "--mesh"
contains "help names mpirun" "$work/out.txt" "mpirun"

printf 'reference: {moment_point: [0.25, 0, 0]}\noutput: {volume: false}\n' > "$work/om6.yaml"
# Five iterations, then the same command with ten continues from the restart file.
check "cfd 5 iterations" 0 "$manta" cfd --mesh "$mesh" --mach 0.8395 --alpha-deg 3.06 \
    --config "$work/om6.yaml" --out "$work/run" --max-iterations 5 --json
cp "$work/out.txt" "$work/first.json"
contains "json coefficients" "$work/first.json" '"CL"'
contains "not converged warning" "$work/err.txt" "not converged"
for f in summary.json history.csv surface.csv surface.vtu restart.bin; do
    if [ -s "$work/run/$f" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $f missing"; fi
done
if [ ! -e "$work/run/flow.vtu" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: output.volume false ignored"; fi
contains "history header" "$work/run/history.csv" "^iteration,wall_s,log10_res_rho"
contains "surface header" "$work/run/surface.csv" "^node,marker,x,y,z,rho,u,v,w,p,Cp,Mach"
contains "surface wall marker" "$work/run/surface.csv" ",WING,"
check "cfd continued" 0 "$manta" cfd --mesh "$mesh" --mach 0.8395 --alpha-deg 3.06 \
    --config "$work/om6.yaml" --out "$work/run" --max-iterations 10 --json
cp "$work/out.txt" "$work/second.json"
if [ "$(json "$work/second.json" "j['resumed_from']")" = "5" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: not resumed from 5"; cat "$work/second.json" | head; fi
rows=$(($(wc -l < "$work/run/history.csv") - 1))
if [ "$rows" -eq 11 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: history has $rows rows, expected 11 (0..10)"; fi

# A restart file of another flow condition is refused; --restart starts over.
check "foreign restart" 2 "$manta" cfd --mesh "$mesh" --mach 0.8395 --alpha-deg 2 --out "$work/run" --max-iterations 2
one_line "foreign restart one line" "$work/err.txt"
contains "foreign restart says --restart" "$work/err.txt" "--restart"
check "--restart" 0 "$manta" cfd --mesh "$mesh" --mach 0.8395 --alpha-deg 2 --out "$work/run" --max-iterations 2 --restart
# --initial: a warm start from another run's solution.
check "--initial" 0 "$manta" cfd --mesh "$mesh" --mach 0.8395 --alpha-deg 3.06 --out "$work/warm" \
    --max-iterations 2 --initial "$work/run/restart.bin"

# Bad input: one line, exit 2.
check "no mach" 2 "$manta" cfd --mesh "$mesh" --out "$work/bad"
one_line "no mach one line" "$work/err.txt"
contains "no mach names --mach" "$work/err.txt" "--mach"
check "mach 0" 2 "$manta" cfd --mesh "$mesh" --mach 0 --out "$work/bad"
one_line "mach 0 one line" "$work/err.txt"
printf 'markers: {WINGS: wall}\n' > "$work/badmarker.yaml"
check "unknown marker" 2 "$manta" cfd --mesh "$mesh" --mach 0.5 --config "$work/badmarker.yaml" --out "$work/bad"
one_line "unknown marker one line" "$work/err.txt"
contains "unknown marker named" "$work/err.txt" "WINGS"
printf 'solver: {cfl_maxx: 5}\n' > "$work/badkey.yaml"
check "unknown key" 2 "$manta" cfd --mesh "$mesh" --mach 0.5 --config "$work/badkey.yaml" --out "$work/bad"
contains "unknown key suggestion" "$work/err.txt" "cfl_max"
printf 'NDIME= 3\nNELEM= 1\n10 0 1 2 7 0\nNPOIN= 3\n0 0 0\n1 0 0\n0 1 0\n' > "$work/broken.su2"
check "broken mesh" 2 "$manta" cfd --mesh "$work/broken.su2" --mach 0.5 --out "$work/bad"
one_line "broken mesh one line" "$work/err.txt"
contains "broken mesh names the file" "$work/err.txt" "broken.su2"

# A table campaign on the Euler source (static table; docs/tables.md): four samples at
# two Mach numbers, each after the first warm-started; a rerun reuses every sample.
cat > "$work/campaign.yaml" <<EOF
schema_version: 1
name: om6-euler
source: {type: euler, mesh: $mesh}
static:
  alpha_deg: [0, 2, 4]
  mach: [0.5, 0.7]
  beta_deg: [0]
  initial_design: {size: 4, seed: 1}
  budget: 4
EOF
check "tables on the euler source" 0 "$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab" --json
contains "euler tables evaluated 4" "$work/out.txt" '"evaluated": 4'
if python3 - "$work/tab/samples.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "done"]
assert len(rows) == 4, len(rows)
for r in rows:
    a, cl = float(r["alpha_deg"]), float(r["CL"])
    # Symmetric section: no lift at zero incidence; about 3.5 per radian of the wing's lift slope.
    assert (abs(cl) < 2e-3) if a == 0 else (0.03 * a < cl < 0.1 * a), (a, cl)
    assert r["source"] == "euler", r["source"]
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: euler table samples"; fi
check "euler tables rerun" 0 "$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab" --json
contains "euler tables rerun reuses" "$work/out.txt" '"evaluated": 0'
printf 'controls:\n  elevator: {deflection_deg: [-5, 0, 5]}\n' >> "$work/campaign.yaml"
# Control tables deflect the CFD configuration's control surfaces: none here, refused before any
# sample (docs/tables.md).
check "euler tables with controls" 2 "$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab2"
contains "euler controls message" "$work/err.txt" "campaign.yaml:11: .*no control surface of mode 'elevator'"
one_line "euler controls message one line" "$work/err.txt"

# One and two processes converge to the same coefficients: np_pair LABEL CONFIG [SU2_CL] runs the
# case serially and with `mpirun -n 2`, compares CL, CD, CMy (2e-5) and, if given, CL with SU2's
# on this mesh (1 %).
np_pair() {
    local label=$1 config=$2 su2_cl=${3:-}
    check "serial $label" 0 "$manta" cfd --mesh "$mesh" --mach 0.8395 --alpha-deg 3.06 \
        --config "$config" --out "$work/${label}1" --json
    cp "$work/out.txt" "$work/${label}1.json"
    check "mpirun -np 2 $label" 0 "$mpiexec" "${mpiflags[@]}" -n 2 "$manta" cfd --mesh "$mesh" \
        --mach 0.8395 --alpha-deg 3.06 --config "$config" --out "$work/${label}2" --json
    cp "$work/out.txt" "$work/${label}2.json"
    if python3 - "$work/${label}1.json" "$work/${label}2.json" "$label" "$su2_cl" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
label, su2_cl = sys.argv[3], sys.argv[4]
assert a["converged"] and b["converged"], (a["reason"], b["reason"])
assert b["processes"] == 2, b["processes"]
for k in ("CL", "CD", "CMy"):
    d = abs(a["coefficients"][k] - b["coefficients"][k])
    print(f"{label} {k}: 1 process {a['coefficients'][k]:.6f}, 2 processes {b['coefficients'][k]:.6f}, |diff| {d:.2e}")
    assert d < 2e-5, k
if su2_cl:
    assert abs(a["coefficients"]["CL"] - float(su2_cl)) < 0.01 * float(su2_cl), a["coefficients"]["CL"]
PY
    then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $label: 1 and 2 processes"; fi
}
if [ -n "$mpiexec" ]; then
    np_pair roe "$work/om6.yaml"
    # JST and its strong wall tangency (rows of wall nodes replaced on each process); SU2 v8.1.0
    # on this mesh: CL 0.278600 (../shared/reference/onera_m6/README.md).
    { cat "$work/om6.yaml"; printf 'numerics: {flux: jst}\n'; } > "$work/om6_jst.yaml"
    np_pair jst "$work/om6_jst.yaml" 0.2786
fi

# Time-accurate runs (`--motion`) on SU2's NACA 64A010 mesh (2-D, turned y up): a short pitching
# motion; kill -9 during the run and the same command resumes to the uninterrupted history byte
# for byte; a restart of another motion, a time step that does not divide the motion, a
# motion without v0 and the bad input below are one-line errors; the deforming mesh motion runs.
ct5=$shared/reference/naca64a010_ct5/mesh_NACA64A010_inv.su2
if [ -f "$ct5" ]; then
    python3 - "$work/pitch.csv" "$work/pitch2.csv" <<'PY'
import math, sys
for name, amp in ((sys.argv[1], 1.0), (sys.argv[2], 2.0)):
    with open(name, "w") as f:
        f.write("# v0: 270.876\n# mach: 0.796\nt,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n")
        for i in range(9):
            t = i * 0.0025
            f.write(f"{t!r},0,0,0,0,{math.radians(amp) * math.sin(100 * t)!r},0,0,0,0\n")
PY
    printf 'mesh: {up: y}\nmarkers: {airfoil: wall}\nreference: {area: 1, moment_point: [0.25, 0, 0]}\nnumerics: {flux: jst, wall: strong}\nunsteady: {max_inner: 4, output_every: 4}\noutput: {checkpoint_interval_s: 0}\n' > "$work/ct5.yaml"
    ucfd=("$manta" cfd --mesh "$ct5" --motion "$work/pitch.csv" --config "$work/ct5.yaml")
    check "cfd --motion" 0 "${ucfd[@]}" --out "$work/u1" --json
    for f in coefficients.csv summary.json restart_unsteady.bin surface.pvd flow.pvd surface_000008.vtu flow_000004.vtu; do
        if [ -f "$work/u1/$f" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --motion wrote no $f"; fi
    done
    contains "coefficients.csv columns" "$work/u1/coefficients.csv" '^t,CL,CD,CY,Cl,Cm,Cn,CX,CZ,alpha,beta,airspeed,inner_iterations,residual_drop$'
    if [ "$(wc -l < "$work/u1/coefficients.csv")" -eq 10 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: coefficients.csv: not 1 + 9 rows"; fi
    contains "summary steps" "$work/u1/summary.json" '"n_steps": 8'
    contains "pvd lists step 8" "$work/u1/surface.pvd" 'surface_000008.vtu'
    # Stopped after 3 steps, then continued: the same history.
    check "cfd --motion --max-steps 3" 0 "${ucfd[@]}" --out "$work/u2" --max-steps 3
    check "cfd --motion continued" 0 "${ucfd[@]}" --out "$work/u2"
    if cmp -s "$work/u1/coefficients.csv" "$work/u2/coefficients.csv"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: stop and continue: coefficients.csv differs"; diff "$work/u1/coefficients.csv" "$work/u2/coefficients.csv" | head; fi
    # kill -9 once the first checkpoint is there, then the same command.
    "${ucfd[@]}" --out "$work/u3" >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 1 600); do [ -f "$work/u3/restart_unsteady.bin" ] && break; sleep 0.05; done
    kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
    killed_at=$(($(wc -l < "$work/u3/coefficients.csv" 2>/dev/null || echo 1) - 1))
    echo "kill -9 after step $killed_at of 8"
    check "cfd --motion after kill -9" 0 "${ucfd[@]}" --out "$work/u3"
    if cmp -s "$work/u1/coefficients.csv" "$work/u3/coefficients.csv"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: kill -9 and resume: coefficients.csv differs"; diff "$work/u1/coefficients.csv" "$work/u3/coefficients.csv" | head; fi
    # Another motion in the same folder: refused, naming both.
    check "restart of another motion" 2 "$manta" cfd --mesh "$ct5" --motion "$work/pitch2.csv" --config "$work/ct5.yaml" --out "$work/u2" --max-steps 4
    one_line "another motion: one line" "$work/err.txt"
    contains "another motion names both" "$work/err.txt" "pitch.csv.*pitch2.csv"
    check "dt that does not divide" 2 "${ucfd[@]}" --out "$work/u4" --dt 0.003
    one_line "dt: one line" "$work/err.txt"
    contains "dt names the duration" "$work/err.txt" "does not divide the duration 0.02"
    grep -v '^# v0' "$work/pitch.csv" > "$work/nov0.csv"
    check "motion without v0" 2 "$manta" cfd --mesh "$ct5" --motion "$work/nov0.csv" --config "$work/ct5.yaml" --out "$work/u5"
    contains "no v0 named" "$work/err.txt" "v0"
    # Bad input of the motion (issue 17, "Bad input"), each a one-line error and exit 2 before
    # the solver starts: missing columns, decreasing times, NaN, a mode that deflects with no
    # control surface, a hinge line off its surface, a deflection and a deforming motion that
    # fold cells, a symmetry marker that is not plane; a restart of the rigid motion refused by the deforming
    # one, its coefficients.csv kept.
    bad_motion() {  # bad_motion NAME FILE PATTERN [CONFIG]
        check "$1" 2 "$manta" cfd --mesh "$ct5" --motion "$2" --config "${4:-$work/ct5.yaml}" --out "$work/bad"
        one_line "$1: one line" "$work/err.txt"
        contains "$1: says what" "$work/err.txt" "$3"
    }
    sed 's/,mode_rudder$//; s/,0$//' "$work/pitch.csv" > "$work/nocol.csv"
    bad_motion "motion with a missing column" "$work/nocol.csv" "nocol.csv:3: missing column 'mode_rudder'"
    awk -F, -v OFS=, 'NR == 6 { $1 = "0.001" } { print }' "$work/pitch.csv" > "$work/decr.csv"
    bad_motion "motion with decreasing times" "$work/decr.csv" "decr.csv:6:.*increas"
    awk -F, -v OFS=, 'NR == 7 { $6 = "nan" } { print }' "$work/pitch.csv" > "$work/nan.csv"
    bad_motion "motion with NaN" "$work/nan.csv" "nan.csv:7:.*'theta'.*finite"
    awk -F, -v OFS=, 'NR > 3 { $8 = "0.1" } { print }' "$work/pitch.csv" > "$work/elev.csv"
    bad_motion "mode with no control surface" "$work/elev.csv" "mode 'elevator' deflects.*no control surface"
    { cat "$work/ct5.yaml"; printf 'control_surfaces: [{mode: elevator, marker: airfoil, hinge: [[5, 0, 0], [5, 1, 0]]}]\n'; } > "$work/hinge.yaml"
    bad_motion "hinge off the surface" "$work/elev.csv" "hinge line .* m from the nearest node of marker 'airfoil'" "$work/hinge.yaml"
    # The whole aerofoil as a control surface about its quarter chord (it slides on the slab's
    # symmetry planes): 82 deg folds cells.
    awk -F, -v OFS=, 'NR > 3 { $8 = sprintf("%.6f", 1.5 * sin(100 * $1)) } { print }' "$work/pitch.csv" > "$work/bigflap.csv"
    { cat "$work/ct5.yaml"; printf 'control_surfaces: [{mode: elevator, marker: airfoil, hinge: [[0.25, -1, 0], [0.25, 0, 0]]}]\n'; } > "$work/flap.yaml"
    bad_motion "deflection that folds cells" "$work/bigflap.csv" "bigflap.csv: t = .*folds at node .*with elevator .* deg; the largest deflection that keeps every cell valid is 0\.[0-9]+ of it" "$work/flap.yaml"
    python3 - "$work/pitch60.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("# v0: 270.876\n# mach: 0.796\nt,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n")
    for i in range(9):
        t = i * 0.0025
        f.write(f"{t!r},0,0,0,0,{math.radians(60) * math.sin(100 * t)!r},0,0,0,0\n")
PY
    sed 's/unsteady: {max_inner: 4, output_every: 4}/unsteady: {max_inner: 4, mesh_motion: deforming}/' "$work/ct5.yaml" > "$work/deform.yaml"
    sed 's/mesh_motion: deforming/mesh_motion: deforming, rigid_radius: 0.6, fixed_radius: 0.8/' "$work/deform.yaml" > "$work/tight.yaml"
    bad_motion "deforming motion that folds cells" "$work/pitch60.csv" "pitch60.csv: t = .*folds at node .*the largest fraction of the motion that keeps every cell valid is 0\.[0-9]+ of it" "$work/tight.yaml"
    sed 's/markers: {airfoil: wall}/markers: {airfoil: wall, farfield: symmetry}/' "$work/deform.yaml" > "$work/curved.yaml"
    bad_motion "symmetry marker not plane" "$work/pitch.csv" "symmetry marker 'farfield' is not plane: node [0-9]+" "$work/curved.yaml"
    check "rigid motion, 1 step" 0 "${ucfd[@]}" --out "$work/u6" --max-steps 1
    cp "$work/u6/coefficients.csv" "$work/u6_before.csv"
    check "deforming restart of a rigid run" 2 "$manta" cfd --mesh "$ct5" --motion "$work/pitch.csv" --config "$work/deform.yaml" --out "$work/u6"
    one_line "deforming restart: one line" "$work/err.txt"
    contains "deforming restart: another motion" "$work/err.txt" "belongs to another motion.*mesh_motion=deforming"
    if cmp -s "$work/u6_before.csv" "$work/u6/coefficients.csv"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: refused restart changed coefficients.csv"; fi
    check "deforming motion, 2 steps" 0 "$manta" cfd --mesh "$ct5" --motion "$work/pitch.csv" --config "$work/deform.yaml" --out "$work/u7" --max-steps 2
    contains "deforming summary" "$work/u7/summary.json" '"mode": "deforming"'
    # Steady control deflections (--elevator-deg, --aileron-deg, --rudder-deg) with flap.yaml's
    # whole aerofoil as the elevator about its quarter chord (sliding on the slab's planes): the
    # trailing edge in surface.csv turned by the deflection, summary.json's deflections_deg, the
    # same deformed geometry on 2 processes, a restart of another deflection refused, and bad
    # input (a mode no surface has, NaN, beyond 45 deg, a fold, with --motion) one-line errors.
    scfd=("$manta" cfd --mesh "$ct5" --config "$work/flap.yaml" --mach 0.5 --max-iterations 2)
    check "cfd undeflected" 0 "${scfd[@]}" --out "$work/d0"
    check "cfd --elevator-deg 2" 0 "${scfd[@]}" --elevator-deg 2 --out "$work/d2" --json
    contains "deflection in the summary" "$work/out.txt" '"deflections_deg"'
    if python3 - "$work/d0/surface.csv" "$work/d2/surface.csv" "$work/d2/summary.json" <<'PY'
import csv, json, math, sys
a, b = ({r["node"]: r for r in csv.DictReader(open(f)) if r["marker"] == "airfoil"} for f in sys.argv[1:3])
te = max(a, key=lambda n: float(a[n]["x"]))  # trailing edge, 0.75 chord aft of the hinge
x0, z0 = float(a[te]["x"]), float(a[te]["z"])
x1, z1 = float(b[te]["x"]), float(b[te]["z"])
turned = math.degrees(math.atan2(z0 - z1, x1 - 0.25))  # trailing edge down: z decreases
print(f"--elevator-deg 2: trailing edge turned by {turned:.6f} deg")
assert abs(turned - 2.0) < 1e-6, turned
j = json.load(open(sys.argv[3]))
assert j["deflections_deg"] == {"elevator": 2.0, "aileron": 0.0, "rudder": 0.0}, j["deflections_deg"]
assert j["control_surfaces"][0]["marker"] == "airfoil", j["control_surfaces"]
PY
    then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: deflected geometry or summary"; fi
    check "restart of another deflection" 2 "${scfd[@]}" --elevator-deg 3 --out "$work/d2"
    one_line "another deflection: one line" "$work/err.txt"
    contains "another deflection names both" "$work/err.txt" "another control deflection \(elevator 2 deg.*this run: elevator 3 deg"
    if [ -n "$mpiexec" ]; then
        check "cfd --elevator-deg 2, 2 processes" 0 "$mpiexec" "${mpiflags[@]}" -np 2 "${scfd[@]}" --elevator-deg 2 --out "$work/d2p"
        if python3 - "$work/d2/surface.csv" "$work/d2p/surface.csv" <<'PY'
import csv, sys
a, b = ({r["node"]: (r["x"], r["y"], r["z"]) for r in csv.DictReader(open(f))} for f in sys.argv[1:3])
assert a == b, "the deformed surfaces of 1 and 2 processes differ"
PY
        then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: deflected geometry on 2 processes"; fi
    fi
    bad_deflection() {  # bad_deflection NAME PATTERN ARGS...
        local name=$1 pattern=$2; shift 2
        check "$name" 2 "$manta" cfd --mesh "$ct5" --mach 0.5 --out "$work/bad" "$@"
        contains "$name: says what" "$work/err.txt" "$pattern"
    }
    bad_deflection "rudder without a surface" "^manta: error: manta cfd: --rudder-deg 1: .*flap.yaml has no control surface of mode 'rudder' \(the modes of its control surfaces: elevator\)" --config "$work/flap.yaml" --rudder-deg 1
    one_line "rudder without a surface: one line" "$work/err.txt"
    bad_deflection "deflection NaN" "--aileron-deg: value 'nan' is not a finite number" --config "$work/flap.yaml" --aileron-deg nan
    bad_deflection "deflection beyond 45 deg" "--elevator-deg: value '46' is outside the range; expected a number in \[-45, 45\] deg" --config "$work/flap.yaml" --elevator-deg 46
    sed 's/hinge: \[\[0.25, -1, 0\], \[0.25, 0, 0\]\]/&, cutoff: 0.05/' "$work/flap.yaml" > "$work/tightflap.yaml"
    bad_deflection "deflection that folds" "--elevator-deg 45 folds the mesh at node [0-9]+ \(dual volume -?[0-9.e-]+ m\^3\)" --config "$work/tightflap.yaml" --elevator-deg 45
    one_line "deflection that folds: one line" "$work/err.txt"
    check "deflection with --motion" 2 "$manta" cfd --mesh "$ct5" --config "$work/flap.yaml" --motion "$work/pitch.csv" --elevator-deg 2 --out "$work/bad"
    contains "deflection with --motion: says what" "$work/err.txt" "--elevator-deg 2 is not taken with --motion; .*mode columns"
    one_line "deflection with --motion: one line" "$work/err.txt"
    if [ -n "$mpiexec" ]; then
        # 1 and 2 processes: the same history to the inner tolerance (3 steps; the inner
        # iterations reach 1.6-3 orders here, so the processes' block-Jacobi preconditioners
        # leave about 1e-3 in CL); stopped after 2 steps on 2 processes, continued on 1.
        sed 's/max_inner: 4, output_every: 4/max_inner: 40, inner_drop: 5, coefficient_tolerance: 1e-7/' "$work/ct5.yaml" > "$work/ct5c.yaml"
        uc=(cfd --mesh "$ct5" --motion "$work/pitch.csv" --config "$work/ct5c.yaml" --max-steps 3)
        check "cfd --motion 1 process" 0 "$manta" "${uc[@]}" --out "$work/p1"
        check "cfd --motion 2 processes" 0 "$mpiexec" "${mpiflags[@]}" -np 2 "$manta" "${uc[@]}" --out "$work/p2"
        if python3 - "$work/p1/coefficients.csv" "$work/p2/coefficients.csv" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(f))) for f in sys.argv[1:3])
assert len(a) == len(b) == 4, (len(a), len(b))
for k in ("CL", "Cm", "CD"):
    d = max(abs(float(x[k]) - float(y[k])) for x, y in zip(a, b))
    print(f"--motion 1 and 2 processes: max |d{k}| {d:.1e}")
    assert d < 3e-3, k
PY
        then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --motion 1 and 2 processes"; fi
    fi
fi

echo "cfd_cli_test: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
