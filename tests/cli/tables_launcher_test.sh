#!/usr/bin/env bash
# A table campaign whose Euler samples run as `manta cfd` jobs through a launcher
# (docs/tables.md, "Launching Euler samples"), on the coarse ONERA M6 mesh: the same coefficients
# as in process, a run folder per sample, a rerun that starts no job, kill -9 of the campaign and
# a rerun that completes it, a launcher that fails. Usage: tables_launcher_test.sh MANTA_BINARY
# SHARED_DIR WORK_DIR [MPIEXEC]
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
check "tables in process" 0 "$manta" tables --campaign "$work/campaign.yaml" --out "$work/tab" --json

# The same campaign with every sample a `manta cfd` job through a launcher (docs/tables.md,
# "Launching Euler samples"): the same coefficients as in process (2e-5; 2 processes when mpirun
# is there), a run folder per sample, a rerun that starts no job, a kill -9 of the campaign
# that a rerun completes, and a launcher that fails: the sample failed with a one-line error.
if [ -n "$mpiexec" ]; then launcher="$mpiexec ${mpiflags[*]} -np 2"; else launcher=""; fi
sed "s|^source: .*|source: {type: euler, mesh: $mesh, launcher: \"$launcher\"}|" "$work/campaign.yaml" > "$work/campaign_jobs.yaml"
check "tables through a launcher" 0 "$manta" tables --campaign "$work/campaign_jobs.yaml" --out "$work/tabj" --json
contains "launched tables evaluated 4" "$work/out.txt" '"evaluated": 4'
n_folders=$(find "$work/tabj/cfd" -name summary.json | wc -l)
if [ "$n_folders" -eq 4 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: launched tables: $n_folders run folders, expected 4"; fi
contains "a job's log" "$(find "$work/tabj/cfd" -name job.log | head -1)" "CL"
if python3 - "$work/tab/samples.csv" "$work/tabj/samples.csv" <<'PY'
import csv, sys
a, b = ({(r["alpha_deg"], r["mach"]): r for r in csv.DictReader(open(f)) if r["status"] == "done"} for f in sys.argv[1:3])
assert a.keys() == b.keys() and len(a) == 4, (a.keys(), b.keys())
for k in a:
    for c in ("CL", "CD", "Cm"):
        d = abs(float(a[k][c]) - float(b[k][c]))
        assert d < 2e-5, (k, c, a[k][c], b[k][c])
print("in process and launched agree to 2e-5 on", len(a), "samples")
PY
then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: launched samples differ from in-process ones"; fi
check "launched tables rerun" 0 "$manta" tables --campaign "$work/campaign_jobs.yaml" --out "$work/tabj" --json
contains "launched rerun reuses" "$work/out.txt" '"evaluated": 0'
# kill -9 the campaign while its first job runs; the rerun finishes with 4 samples.
"$manta" tables --campaign "$work/campaign_jobs.yaml" --out "$work/tabk" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -n "$(find "$work/tabk/cfd" -name job.log 2>/dev/null)" ] && break; sleep 0.05; done
sleep 1; kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
check "launched tables after kill -9" 0 "$manta" tables --campaign "$work/campaign_jobs.yaml" --out "$work/tabk" --json
contains "after kill -9: 4 done" "$work/tabk/samples.csv" "done"
n_done=$(grep -c ",done," "$work/tabk/samples.csv" || true)
if [ "$n_done" -eq 4 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: after kill -9: $n_done samples done, expected 4"; fi
sed "s|^source: .*|source: {type: euler, mesh: $mesh, launcher: \"false\"}|" "$work/campaign.yaml" > "$work/campaign_false.yaml"
check "a launcher that fails" 1 "$manta" tables --campaign "$work/campaign_false.yaml" --out "$work/tabf"
contains "failed launcher: too few samples" "$work/err.txt" "0 done samples \(4 failed\)"
contains "failed launcher: the error names the status and log" "$work/tabf/samples.csv" "exited with status 1 \(log .*job.log"

# A launched campaign with a table of a control the mesh has no surface for (the ONERA M6 wing
# has none): refused before any job starts, naming the campaign key.
cp "$work/campaign_jobs.yaml" "$work/campaign_rudder.yaml"
printf 'controls:\n  rudder: {deflection_deg: [-5, 0, 5]}\n' >> "$work/campaign_rudder.yaml"
check "launched tables with a control the mesh lacks" 2 "$manta" tables --campaign "$work/campaign_rudder.yaml" --out "$work/tabr"
contains "launched control message" "$work/err.txt" "campaign_rudder.yaml:.*no control surface of mode 'rudder'"
if [ ! -d "$work/tabr/cfd" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: a job was started for a refused campaign"; fi

echo "tables_launcher_test: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
