#!/usr/bin/env bash
# A table campaign with control increments and dynamic derivatives whose Euler samples run as
# `manta cfd` jobs through a launcher (docs/tables.md, "Launching Euler samples"), on a tiny
# Ranger 2000 full mesh that the campaign makes itself (every size x 8, first order): jobs with
# --elevator-deg and --p-hat/--q-hat/--r-hat, their folders named by them.
# - A launcher that fails the deflected jobs: the campaign fails (exit 1), the failed samples
#   carry the one-line error (exit status, log, its last line), the static ones are done.
# - The same store with `launcher: ""` and --retry-failed: the failed samples run again, every
#   section filled, 14 run folders, damping derivatives Cl_p, Cm_q, Cn_r < 0.
# - The same campaign through `mpirun -np 2` (when MPI is there): the same samples to the
#   round-off of the partitioning.
# Usage: tables_launcher_controls_test.sh MANTA_BINARY SOURCE_DIR WORK_DIR [MPIEXEC]
set -u
manta=$1
src=$2
work=$3
mpiexec=${4:-}
mpiflags=()
if [ -n "$mpiexec" ] && "$mpiexec" --version 2>&1 | grep -qiE "open ?mpi|openrte"; then
    mpiflags=(--oversubscribe --allow-run-as-root)
fi
rm -rf "$work"; mkdir -p "$work"
cli_show="tail -20"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
ok() {  # ok NAME COMMAND...: the command succeeds
    local name=$1; shift
    if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $name"; fi
}

cp "$src/examples/ranger2000/aircraft.yaml" "$work/ranger.yaml"
printf '%s\n' 'numerics: {order: 1}' 'solver: {residual_drop: 3, max_iterations: 400}' \
    'output: {checkpoint_interval_s: 0, volume: false, surface: false}' > "$work/cfd.yaml"
# A launcher that fails the deflected jobs and runs the others.
printf '%s\n' 'case " $* " in *" --elevator-deg "*) echo "no deflected jobs here" >&2; exit 3;; esac' \
    'exec "$@"' > "$work/no_deflections.sh"
campaign() {  # campaign FILE SOURCE_LINES...
    local file=$1; shift
    { printf '%s\n' 'schema_version: 1' 'name: ranger-full-tiny' 'source:' '  type: euler' "$@" \
        '  config: cfd.yaml' 'static:' '  alpha_deg: [0, 4]' '  mach: [0.3, 0.5]' '  beta_deg: [0]' \
        '  initial_design: {size: 4, seed: 1}' '  budget: 4' 'controls:' \
        '  elevator: {deflection_deg: [-5, 0, 5], alpha_deg: [0, 4], mach: [0.3], samples: 4}' \
        'dynamic: {alpha_deg: [4], mach: [0.3], rate_step: 0.02}'; } > "$file"
}
meshed=('  aircraft: ranger.yaml' '  mesh: {model: full, level: coarse, size_factor: 8}')
campaign "$work/failing.yaml" "${meshed[@]}" "  launcher: \"sh $work/no_deflections.sh\""
check "deflected jobs fail" 1 "$manta" tables --campaign "$work/failing.yaml" --out "$work/tab"
if [ "$(wc -l < "$work/err.txt")" -ge 1 ] && [ "$(grep -c "manta: error" "$work/err.txt")" -eq 1 ]; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: not one error line"; cat "$work/err.txt"; fi
contains "failed: the error names the control samples" "$work/err.txt" "elevator"
contains "failed samples: status, log and last line" "$work/tab/samples.csv" \
    "exited with status 3 \(log .*_de[-+]5.000000_da\+0.000000_dr\+0.000000/job.log: no deflected jobs here\)"
n_static=$(grep -cE "^[0-9]+,static,done," "$work/tab/samples.csv" || true)
if [ "$n_static" -eq 4 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $n_static static samples done, expected 4"; head -5 "$work/tab/samples.csv"; fi

# The same store without a launcher: the failed samples run again, then the dynamic ones.
campaign "$work/jobs.yaml" "${meshed[@]}" '  launcher: ""'
check "retry the failed samples through jobs" 0 "$manta" tables --campaign "$work/jobs.yaml" --out "$work/tab" --retry-failed --json
n_folders=$(find "$work/tab/cfd" -name summary.json | wc -l)
if [ "$n_folders" -eq 14 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $n_folders run folders, expected 14 (4 static, 4 elevator, 6 rates)"; ls "$work/tab/cfd"; fi
ok "a deflected folder" test -f "$(ls -d "$work"/tab/cfd/M0.300000_a+*_b+0.000000_de+5.000000_da+0.000000_dr+0.000000 | head -1)/summary.json"
ok "a rotating folder" test -f "$work/tab/cfd/M0.300000_a+4.000000_b+0.000000_p+0.000000_q+0.020000_r+0.000000/summary.json"
contains "a rotating job's words" "$work/tab/cfd/M0.300000_a+4.000000_b+0.000000_p-0.020000_q+0.000000_r+0.000000/job.log" "p_hat -0.02"
if python3 - "$work/tab" <<'PY'
import csv, json, sys
out = sys.argv[1]
s = json.load(open(out + "/cfd/M0.300000_a+4.000000_b+0.000000_p+0.000000_q+0.000000_r+0.020000/summary.json"))
assert s["rates"] == {"p_hat": 0.0, "q_hat": 0.0, "r_hat": 0.02}, s["rates"]
d = next(csv.DictReader(l for l in open(out + "/dynamic.csv") if not l.startswith("#")))
for k in ("Cl_p", "Cm_q", "Cn_r"):
    assert float(d[k]) < 0, (k, d[k])
assert float(d["CL_q"]) > 0, d["CL_q"]
print("damping:", {k: round(float(d[k]), 4) for k in ("Cl_p", "Cm_q", "Cn_r", "CL_q")})
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: the rates' summaries or the damping derivatives"; fi
contains "the database has the control table" "$work/tab/database.yaml" "elevator"

# Through mpirun -np 2 on the mesh the first campaign made: the same samples to round-off.
if [ -n "$mpiexec" ]; then
    mesh=$work/tab/mesh/ranger_full_coarse.su2
    campaign "$work/mpi.yaml" "  mesh: $mesh" "  launcher: \"$mpiexec ${mpiflags[*]} -np 2\""
    check "the campaign through mpirun -np 2" 0 "$manta" tables --campaign "$work/mpi.yaml" --out "$work/tabm" --json
    contains "a job on 2 processes" "$work/tabm/cfd/M0.300000_a+4.000000_b+0.000000_p+0.020000_q+0.000000_r+0.000000/job.log" "2 processes"
    if python3 - "$work/tab/cfd" "$work/tabm/cfd" <<'PY'
import glob, json, os, sys
a, b = sys.argv[1:3]
names = sorted(os.path.basename(os.path.dirname(f)) for f in glob.glob(a + "/*/summary.json"))
assert len(names) == 14, names
worst = 0.0
for n in names:
    ca = json.load(open(f"{a}/{n}/summary.json"))["coefficients"]
    cb = json.load(open(f"{b}/{n}/summary.json"))["coefficients"]
    for c in ("CL", "CD", "CY", "Cl", "Cm", "Cn"):
        worst = max(worst, abs(ca[c] - cb[c]))
print(f"1 and 2 processes: max |difference| {worst:.3g} over 14 samples")
assert worst < 1e-4, worst
PY
    then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: 1 and 2 processes differ"; fi
fi

echo "tables_launcher_controls_test: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
