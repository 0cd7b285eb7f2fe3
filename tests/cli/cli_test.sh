#!/usr/bin/env bash
# End-to-end checks of the manta CLI. Usage: cli_test.sh MANTA_BINARY REPO_ROOT WORK_DIR
# Prints "N passed, N failed" and exits non-zero on any failure.
set -u
manta=$1
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
ranger=$root/examples/ranger2000/aircraft.yaml

json_ok() {  # json_ok NAME  (stdout of the last check must be one JSON object)
    if python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert isinstance(d, dict)' "$work/out.txt" 2>/dev/null \
       || { command -v python3 >/dev/null || grep -q '^{' "$work/out.txt"; }; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1)); echo "FAIL: $1: stdout is not one JSON object"; head -5 "$work/out.txt"
    fi
}

# --help and --version
check "manta --help" 0 "$manta" --help
contains "help lists subcommands" "$work/out.txt" "atmosphere"
check "manta --version" 0 "$manta" --version
contains "version text" "$work/out.txt" "manta [0-9]+\.[0-9]+\.[0-9]+"
for sub in atmosphere "config check" trim modes simulate demo vlm vlm-unsteady vlm-oscillation oscillation tables optimise replay report; do
    # shellcheck disable=SC2086
    check "manta $sub --help" 0 "$manta" $sub --help
done
check "no subcommand is bad input" 2 "$manta"
check "unknown subcommand" 2 "$manta" fly
check "unknown option" 2 "$manta" atmosphere --altitude 1000 --colour red

# atmosphere
check "atmosphere json" 0 "$manta" atmosphere --altitude 5000 --json
json_ok "atmosphere json"
contains "atmosphere T(5 km)" "$work/out.txt" '"temperature": 255\.6'
check "atmosphere text" 0 "$manta" atmosphere --altitude 0
contains "atmosphere p0" "$work/out.txt" "101325"
check "atmosphere out of range" 2 "$manta" atmosphere --altitude 100000
contains "range message" "$work/err.txt" "outside the US Standard Atmosphere 1976 range"
check "atmosphere non-number" 2 "$manta" atmosphere --altitude high

# config check
check "config check ranger" 0 "$manta" config check "$ranger" --json
json_ok "config check json"
printf 'schema_version: 1\nname: X\nrefrence: {}\n' > "$work/bad.yaml"
check "config check bad file" 2 "$manta" config check "$work/bad.yaml"
contains "bad key named with line" "$work/err.txt" "bad.yaml:3.*refrence"
check "config check missing file" 2 "$manta" config check "$work/none.yaml"
contains "missing file named" "$work/err.txt" "none.yaml"

# trim and modes
check "trim level" 0 "$manta" trim --aircraft "$ranger" --speed 150 --altitude 3000 --json
json_ok "trim json"
contains "trim has alpha" "$work/out.txt" '"alpha"'
check "trim turn" 0 "$manta" trim --aircraft "$ranger" --speed 150 --altitude 3000 --turn-rate-deg-s 10 --json
check "trim climb" 0 "$manta" trim --aircraft "$ranger" --speed 150 --altitude 3000 --climb-angle-deg 5
check "trim climb and turn exclusive" 2 "$manta" trim --aircraft "$ranger" --speed 150 --altitude 3000 --climb-angle-deg 5 --turn-rate-deg-s 3
check "trim impossible (too slow)" 1 "$manta" trim --aircraft "$ranger" --speed 20 --altitude 3000
check "trim negative speed" 2 "$manta" trim --aircraft "$ranger" --speed -5 --altitude 3000
check "modes" 0 "$manta" modes --aircraft "$ranger" --speed 150 --altitude 3000 --json
json_ok "modes json"
contains "modes short period" "$work/out.txt" "short"

# simulate
printf 't,elevator_deg\n0,0\n1,-2\n2,2\n3,0\n' > "$work/inputs.csv"
check "simulate" 0 "$manta" simulate --aircraft "$ranger" --inputs "$work/inputs.csv" --duration 5 --out "$work/traj.csv" --json
json_ok "simulate json"
contains "trajectory header" "$work/traj.csv" "^t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r"
printf 't,elevator_deg\n0,0\n1,-2\n1,2\n' > "$work/bad_inputs.csv"
check "simulate duplicated time" 2 "$manta" simulate --aircraft "$ranger" --inputs "$work/bad_inputs.csv" --duration 5 --out "$work/t2.csv"
contains "duplicated time names line" "$work/err.txt" "bad_inputs.csv:4"
printf 't,elevator_deg\n0,0\n1,nan\n' > "$work/nan_inputs.csv"
check "simulate NaN input" 2 "$manta" simulate --aircraft "$ranger" --inputs "$work/nan_inputs.csv" --duration 5 --out "$work/t3.csv"

# vlm (coarse lattice: the check is of the command, not of the solver)
check "vlm ranger json" 0 "$manta" vlm --aircraft "$ranger" --alpha-deg 2 --mach 0.3 --altitude 3000 --n-chord 4 --strip-width 0.05 --json --span-csv "$work/span.csv" --vtu "$work/panels.vtu"
json_ok "vlm json"
contains "vlm derivatives" "$work/out.txt" '"static_margin"'
contains "vlm viscous part" "$work/out.txt" '"CD_profile"'
contains "span loading header" "$work/span.csv" "^surface,mirrored,y,z,chord,width,cl"
contains "vtu" "$work/panels.vtu" "UnstructuredGrid"
check "vlm unknown control" 2 "$manta" vlm --aircraft "$ranger" --n-chord 2 --strip-width 0.1 --mach 0.3 --control flap=5
contains "unknown control named" "$work/err.txt" "control 'flap' is not on this aircraft"
check "vlm bad control syntax" 2 "$manta" vlm --aircraft "$ranger" --n-chord 2 --strip-width 0.1 --mach 0.3 --control flap:5
check "vlm supersonic" 2 "$manta" vlm --aircraft "$ranger" --mach 1.2
printf 'Plate\n0.0\n0 0 0.0\n4.0 1.0 4.0\n0.25 0 0\nSURFACE\nWing\n4 1.0 8 1.0\nYDUPLICATE\n0.0\nSECTION\n0 0 0 1 0\nSECTION\n0 2 0 1 0\n' > "$work/plate.avl"
check "vlm avl file" 0 "$manta" vlm --aircraft "$work/plate.avl" --alpha-deg 4 --json
json_ok "vlm avl json"
printf 'Plate\n0.0\n0 0 0.0\n4.0 1.0 4.0\n0.25 0 0\nSURFACE\nWing\n4 1.0 8 1.0\nSECTION\n0 0 0 -1 0\nSECTION\n0 2 0 1 0\n' > "$work/bad.avl"
check "vlm bad avl chord" 2 "$manta" vlm --aircraft "$work/bad.avl"
contains "bad chord names file and line" "$work/err.txt" "bad.avl:[0-9]+"

# vlm-unsteady and vlm-oscillation (coarse lattices)
{ echo '# v0: 100.0'; echo 't,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder'
  for i in 0 1 2 3 4 5 6 7 8 9 10; do echo "0.0$i,0,0,0,0,0.05,0,0,0,0" | sed 's/0.010,/0.10,/'; done; } > "$work/motion.csv"
check "vlm-unsteady" 0 "$manta" vlm-unsteady --aircraft "$work/plate.avl" --motion "$work/motion.csv" --out "$work/uvlm" --json
json_ok "vlm-unsteady json"
contains "uvlm history" "$work/uvlm/coefficients.csv" "^t,CL,CD,CY,Cl,Cm,Cn"
contains "uvlm wake" "$work/uvlm/wake.vtu" "UnstructuredGrid"
printf 't,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n0,0,0,0,0,0,0,0,0,0\n0,0,0,0,0,0,0,0,0,0\n' > "$work/bad_motion.csv"
check "vlm-unsteady non-monotonic time" 2 "$manta" vlm-unsteady --aircraft "$work/plate.avl" --motion "$work/bad_motion.csv" --out "$work/uvlm2" --speed 100
contains "motion error names line" "$work/err.txt" "bad_motion.csv:3"
check "vlm-oscillation" 0 "$manta" vlm-oscillation --aircraft "$work/plate.avl" --axis roll --k 0.05 --steps-per-period 16 --json
json_ok "vlm-oscillation json"
contains "oscillation out of phase" "$work/out.txt" '"out_of_phase_fourier"'
check "vlm-oscillation bad axis" 2 "$manta" vlm-oscillation --aircraft "$work/plate.avl" --axis spin
# oscillation --source vlm|euler (vlm-oscillation is its vlm case): the same derivatives, its
# JSON keys, a checkpoint that a rerun answers from, and bad options as one-line errors.
one_line() {  # one_line NAME  (stderr of the last check: one line, besides CLI11's help hint)
    if [ "$(grep -vc '^Run with --help' "$work/err.txt")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: stderr is not one line"; sed 's/^/    /' "$work/err.txt" | head -5; fi
}
osc_args=(--aircraft "$work/plate.avl" --axis pitch --k 0.05 --alpha-deg 2 --steps-per-period 16 --json)
check "vlm-oscillation pitch" 0 "$manta" vlm-oscillation "${osc_args[@]}"
cp "$work/out.txt" "$work/vlm_osc.json"
check "oscillation --source vlm" 0 "$manta" oscillation --source vlm "${osc_args[@]}"
json_ok "oscillation json"
cp "$work/out.txt" "$work/osc.json"
for key in '"source": "vlm"' '"omega"' '"steps": 48' '"resumed_from": -1' '"in_phase_regression"' '"r_squared"' '"Cm"'; do
    contains "oscillation json $key" "$work/osc.json" "$key"
done
if python3 -c 'import json,sys; a,b=(json.load(open(f)) for f in sys.argv[1:]); sys.exit(0 if a["coefficients"]==b["coefficients"] else 1)' "$work/vlm_osc.json" "$work/osc.json"; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: oscillation --source vlm and vlm-oscillation differ"; fi
check "oscillation checkpoint" 0 "$manta" oscillation "${osc_args[@]}" --checkpoint "$work/osc.ckpt" --checkpoint-seconds 0 --history "$work/osc_history.csv"
contains "oscillation history" "$work/osc_history.csv" "^t,CL,CD,CY,Cl,Cm,Cn"
check "oscillation resumes from a finished checkpoint" 0 "$manta" oscillation "${osc_args[@]}" --checkpoint "$work/osc.ckpt"
contains "oscillation resumed" "$work/out.txt" '"resumed_from": 48'
if python3 -c 'import json,sys; a,b=(json.load(open(f)) for f in sys.argv[1:]); sys.exit(0 if a["coefficients"]==b["coefficients"] else 1)' "$work/osc.json" "$work/out.txt"; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: oscillation from its checkpoint differs"; fi
check "oscillation checkpoint of another run" 2 "$manta" oscillation --aircraft "$work/plate.avl" --k 0.1 --steps-per-period 16 --checkpoint "$work/osc.ckpt"
contains "another run named" "$work/err.txt" "osc.ckpt: checkpoint of another oscillation"
one_line "checkpoint of another run"
check "oscillation bad axis" 2 "$manta" oscillation --aircraft "$work/plate.avl" --axis spin
contains "bad axis message" "$work/err.txt" "--axis 'spin'; expected pitch, roll, yaw or plunge"
one_line "bad axis"
for bad in "--k 0" "--k -0.1" "--periods 1" "--steps-per-period 4" "--amplitude-deg 0" "--source cfd" "--checkpoint-seconds -1"; do
    # shellcheck disable=SC2086
    check "oscillation $bad" 2 "$manta" oscillation --aircraft "$work/plate.avl" $bad
    one_line "oscillation $bad"
done
check "oscillation euler without a mesh" 2 "$manta" oscillation --source euler
contains "euler needs a mesh" "$work/err.txt" "--source euler: no --mesh"
one_line "euler without a mesh"
check "oscillation euler with vlm options" 2 "$manta" oscillation --source euler --mesh "$work/plate.avl" --n-chord 4
contains "euler refuses vlm options" "$work/err.txt" "are for --source vlm"
check "oscillation vlm without an aircraft" 2 "$manta" oscillation --source vlm
contains "vlm needs an aircraft" "$work/err.txt" "--source vlm: no --aircraft"
check "oscillation vlm with a mesh" 2 "$manta" oscillation --aircraft "$work/plate.avl" --mesh "$work/plate.avl"
contains "vlm refuses --mesh" "$work/err.txt" "--mesh and --config are for --source euler"

# tables: a small analytic campaign, errors, kill -9 and resume, changed source fingerprint
campaigns=$root/examples/campaigns
check "tables small analytic" 0 "$manta" tables --campaign "$campaigns/analytic-small.yaml" --out "$work/tab" --jobs 2 --json
json_ok "tables json"
contains "tables counts" "$work/out.txt" '"evaluated": 90'
for f in database.yaml tables.csv dynamic.csv samples.csv ceasiom_aero.txt ceasiom_control.txt jsbsim_aero.xml summary.json plot_elevator.svg; do
    if [ -s "$work/tab/$f" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: tables output $f missing"; fi
done
contains "tables csv header" "$work/tab/tables.csv" "^table,alpha_deg,mach,beta_deg,delta_deg,CL,CD,CY,Cl,Cm,Cn,sigma_CL"
contains "ceasiom header" "$work/tab/ceasiom_aero.txt" "alpha +Mach +beta +p_hat +q_hat +r_hat +CL +CD +Cm +CY +Cl +Cn"
if command -v python3 >/dev/null; then
    check "jsbsim xml parses" 0 python3 -c 'import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); assert r.tag == "aerodynamics" and len(r.findall("axis")) == 6' "$work/tab/jsbsim_aero.xml"
fi
check "tables database loads" 0 "$manta" config check "$work/tab/database.yaml"
# The generated database flies: the Ranger with its aero model replaced by the tables.
sed '/^aero:/,$d' "$ranger" > "$work/tab/aircraft.yaml"
printf 'aero:\n  database: database.yaml\n' >> "$work/tab/aircraft.yaml"
check "trim on generated tables" 0 "$manta" trim --aircraft "$work/tab/aircraft.yaml" --speed 150 --altitude 3000 --json
json_ok "trim on generated tables json"
check "tables rerun reuses everything" 0 "$manta" tables --campaign "$campaigns/analytic-small.yaml" --out "$work/tab" --json
contains "tables rerun evaluates nothing" "$work/out.txt" '"evaluated": 0'
contains "tables rerun reuses" "$work/out.txt" '"reused": 90'
printf 'schema_version: 1\nname: bad\nsource: {type: analytic}\nstatic:\n  budjet: 30\n' > "$work/bad_campaign.yaml"
check "tables bad key" 2 "$manta" tables --campaign "$work/bad_campaign.yaml" --out "$work/tab_bad"
contains "tables bad key line" "$work/err.txt" "bad_campaign.yaml:5.*budjet.*did you mean 'budget'"
printf 'schema_version: 1\nname: bad\nsource: {type: euler}\n' > "$work/euler_campaign.yaml"
check "tables euler without mesh" 2 "$manta" tables --campaign "$work/euler_campaign.yaml" --out "$work/tab_bad"
contains "tables euler message" "$work/err.txt" "euler_campaign.yaml:3.*source.mesh"
sed 's/type: analytic/type: analytic\n  parameters: {CL_alpha: 5.5}/' "$campaigns/analytic-small.yaml" > "$work/changed.yaml"
check "tables changed fingerprint" 2 "$manta" tables --campaign "$work/changed.yaml" --out "$work/tab"
contains "tables fingerprint message" "$work/err.txt" "samples.sqlite.*fingerprint 'analytic:[0-9a-f]+.*fingerprint 'analytic:[0-9a-f]+.*--accept-changed-source"
check "tables accept changed source" 0 "$manta" tables --campaign "$work/changed.yaml" --out "$work/tab" --accept-changed-source
check "tables restart" 0 "$manta" tables --campaign "$work/changed.yaml" --out "$work/tab" --restart --json
contains "tables restart evaluates all" "$work/out.txt" '"reused": 0'
# kill -9 part-way, resume: the same outputs as an uninterrupted run, no sample computed twice
check "tables slow reference" 0 "$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/slow_ref" --jobs 2
"$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/slow" --jobs 2 >/dev/null 2>&1 &
pid=$!
sleep 0.8
kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
check "tables resume after kill -9" 0 "$manta" tables --campaign "$campaigns/analytic-slow.yaml" --out "$work/slow" --jobs 2 --json
cp "$work/out.txt" "$work/resume.json"
contains "tables resume reports reused samples" "$work/err.txt" "resuming from .*samples.sqlite: [1-9][0-9]* finished samples reused"
# the first "reused"/"evaluated" keys in the pretty-printed JSON are the totals of "samples"
reused=$(grep -m1 -oE '"reused": [0-9]+' "$work/resume.json" | grep -oE '[0-9]+$')
evaluated=$(grep -m1 -oE '"evaluated": [0-9]+' "$work/resume.json" | grep -oE '[0-9]+$')
if [ "${reused:-0}" -gt 0 ] && [ $((reused + evaluated)) -eq 74 ]; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: resumed run: reused ${reused:-?} + evaluated ${evaluated:-?} != 74"; fi
for f in database.yaml tables.csv dynamic.csv ceasiom_aero.txt ceasiom_control.txt jsbsim_aero.xml; do
    if cmp -s "$work/slow_ref/$f" "$work/slow/$f"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: resumed $f differs from the uninterrupted run"; fi
done

# optimise: the generic validation problems of the optimal-control module
check "optimise brachistochrone" 0 "$manta" optimise --problem brachistochrone --nodes 30 --json
json_ok "optimise json"
contains "optimise converged" "$work/out.txt" '"converged": true'
contains "optimise brachistochrone time" "$work/out.txt" '"final_time_error": (-?[0-9.]+e-(0[7-9]|1[0-9])|-?0\.0,)'
check "optimise climb" 0 "$manta" optimise --problem min-time-to-climb --nodes 40 --json
contains "optimise climb time" "$work/out.txt" '"final_time": 321\.(0[89]|1[0-3])'
check "optimise double integrator refined" 0 "$manta" optimise --problem double-integrator --nodes 20 --refine --out "$work/di" --json
contains "optimise refined segments" "$work/out.txt" '"segments": 2'
[ -s "$work/di/solution.csv" ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL: optimise wrote no solution.csv"; }
check "optimise failed run" 1 "$manta" optimise --problem min-time-to-climb --max-iter 3 --out "$work/opt_fail"
[ -s "$work/opt_fail/best_iterate.csv" ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL: optimise failure wrote no best_iterate.csv"; }
check "optimise level turn (aircraft)" 0 "$manta" optimise --aircraft "$ranger" --manoeuvre "$root/examples/ranger2000/manoeuvres/level_turn.yaml" --out "$work/turn" --json
json_ok "optimise aircraft json"
contains "optimise aircraft converged" "$work/out.txt" '"converged": true'
[ -s "$work/turn/trajectory.csv" ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL: optimise wrote no trajectory.csv"; ls "$work/turn"; }
[ -s "$work/turn/trajectory_dense.csv" ] && [ -s "$work/turn/flight_path.svg" ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL: optimise wrote no trajectory_dense.csv or flight_path.svg"; }
contains "optimise trajectory header" "$work/turn/trajectory.csv" '^t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder,throttle,phase,'
contains "optimise trajectory metadata" "$work/turn/trajectory.csv" '^# phases: manoeuvre$'
check "optimise --tables" 1 "$manta" optimise --aircraft "$ranger" --manoeuvre "$root/examples/ranger2000/manoeuvres/level_turn.yaml" --tables "$work/tab/database.yaml" --max-iter 5 --out "$work/turn_tab" --json
contains "optimise --tables used" "$work/turn_tab/summary.json" '"aero_tables": ".*database.yaml"'
check "optimise needs a problem or an aircraft" 2 "$manta" optimise --nodes 20
check "optimise too few nodes" 2 "$manta" optimise --problem min-time-to-climb --nodes 1

# demo: the whole pipeline on the level turn (--quick), then a second run that keeps every stage
check "demo quick" 0 "$manta" demo --quick --out "$work/demo" --jobs 2
contains "demo report path" "$work/out.txt" 'Report: .*/demo/report.html'
for f in report.html run.json tables/database.yaml fly/summary.json manoeuvres/level_turn/trajectory_dense.csv replay/level_turn/comparison.csv replay/level_turn/summary.json logs/replay_level_turn.log; do
    if [ -s "$work/demo/$f" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: demo output $f missing"; fi
done
contains "demo run.json complete" "$work/demo/run.json" '"status": "complete"'
# trim, modes and simulate on the demo's generated tables instead of the aircraft file's model
check "trim on tables" 0 "$manta" trim --aircraft "$ranger" --tables "$work/demo/tables" --speed 150 --altitude 3000 --json
json_ok "trim on tables json"
cp "$work/out.txt" "$work/trim_tables.json"
check "trim on the aircraft's model" 0 "$manta" trim --aircraft "$ranger" --speed 150 --altitude 3000 --json
if python3 -c 'import json,sys; a=json.load(open(sys.argv[1])); b=json.load(open(sys.argv[2])); sys.exit(0 if abs(a["alpha"] - b["alpha"]) > 1e-4 else 1)' "$work/trim_tables.json" "$work/out.txt"; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: trim --tables gave the aircraft model's alpha"; fi
check "modes on tables" 0 "$manta" modes --aircraft "$ranger" --tables "$work/demo/tables/database.yaml" --speed 150 --altitude 3000 --json
check "simulate on tables" 0 "$manta" simulate --aircraft "$ranger" --tables "$work/demo/tables" --inputs "$work/inputs.csv" --duration 2 --out "$work/traj_tables.csv"
check "trim tables folder without database" 2 "$manta" trim --aircraft "$ranger" --tables "$work/demo/fly" --speed 150 --altitude 3000
contains "tables folder message" "$work/err.txt" 'a folder without database.yaml'
check "demo resumed" 0 "$manta" demo --quick --out "$work/demo" --jobs 2
contains "demo keeps finished stages" "$work/out.txt" 'optimise level_turn: already done'
contains "demo keeps the replay" "$work/out.txt" 'replay level_turn: already done'
# (--fidelity euler runs for days; its quick run is tests/cli/demo_euler_test.sh)
check "demo unknown fidelity" 2 "$manta" demo --fidelity cfd --out "$work/demo_bad_fidelity"
contains "demo unknown fidelity message" "$work/err.txt" "'cfd' is not a fidelity; expected vlm or euler"
check "demo unknown manoeuvre" 2 "$manta" demo --manoeuvres loop_the_loop --out "$work/demo_bad"
contains "demo unknown manoeuvre message" "$work/err.txt" "'loop_the_loop' is neither"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
