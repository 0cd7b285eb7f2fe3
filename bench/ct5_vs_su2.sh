#!/usr/bin/env bash
# Benchmark of issue 17 (docs/performance.md#pitching-naca-64a010-ct5-per-physical-step): seconds
# per physical step of the pitching NACA 64A010 (AGARD CT5 conditions, SU2's mesh of
# ../shared/reference/naca64a010_ct5/), MANTA against SU2 v8, one process each, run alternately
# (MANTA SU2 MANTA SU2 ...) for ROUNDS rounds. Both start from the free stream at t = 0 and run
# STEPS physical steps of dt = T/25: MANTA `manta cfd --motion` with
# tests/data/naca64a010_ct5/ct5_rigid.yaml, SU2 `ct5_rigid_su2v8.cfg` with TIME_ITER = STEPS
# (110 inner iterations per step). Per run and per physical step: wall and CPU (user + system)
# time of the whole process (GNU time; start-up included, about 1 s for either), inner
# iterations, the peak resident memory, and the load average (1 min) before and after; MANTA's
# solve alone (wall, summary.json) beside. SU2's history column Time(sec) is not used: in the
# serial build it follows the CPU clock. Prints the medians, the spread (min-max) and the ratio
# MANTA / SU2 of the medians, for wall and CPU time.
#
# Usage: bench/ct5_vs_su2.sh [--rounds N] [--steps N] [--build DIR] [--su2 SU2_CFD]
#                            [--su2-cfg FILE] [--work DIR] [--keep]
# Defaults: 3 rounds, 10 steps, build, $SU2_CFD or /work/peers/SU2/build-serial/SU2_CFD/src/SU2_CFD,
# ../shared/reference/naca64a010_ct5/ct5_rigid_su2v8.cfg, a temporary folder (removed unless --keep).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rounds=3
steps=10
build="$root/build"
su2=${SU2_CFD:-/work/peers/SU2/build-serial/SU2_CFD/src/SU2_CFD}
ref="$root/../shared/reference/naca64a010_ct5"
[ -d "$ref" ] || ref=/work/shared/reference/naca64a010_ct5
su2_cfg="$ref/ct5_rigid_su2v8.cfg"
work=""
keep=0
while [ $# -gt 0 ]; do
    case "$1" in
        --rounds) rounds=$2; shift 2 ;;
        --steps) steps=$2; shift 2 ;;
        --build) build=$2; shift 2 ;;
        --su2) su2=$2; shift 2 ;;
        --su2-cfg) su2_cfg=$2; shift 2 ;;
        --work) work=$2; shift 2 ;;
        --keep) keep=1; shift ;;
        *) echo "ct5_vs_su2.sh: unknown argument '$1'; expected --rounds, --steps, --build, --su2, --su2-cfg, --work or --keep" >&2; exit 2 ;;
    esac
done
manta="$build/bin/manta"
mesh="$ref/mesh_NACA64A010_inv.su2"
data="$root/tests/data/naca64a010_ct5"
timer=/usr/bin/time
for f in "$manta" "$su2" "$timer"; do
    [ -x "$f" ] || { echo "ct5_vs_su2.sh: $f is not an executable" >&2; exit 1; }
done
for f in "$mesh" "$su2_cfg" "$data/ct5_rigid.yaml" "$data/ct5_rigid_motion.csv"; do
    [ -f "$f" ] || { echo "ct5_vs_su2.sh: no file $f" >&2; exit 1; }
done
command -v python3 > /dev/null || { echo "ct5_vs_su2.sh: python3 is needed for the medians" >&2; exit 1; }
if [ -z "$work" ]; then
    work=$(mktemp -d)
    [ "$keep" = 1 ] || trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
load() { cut -d' ' -f1 /proc/loadavg; }

# SU2 runs in its own folder with the mesh beside the configuration.
mkdir -p "$work/su2"
cp "$mesh" "$work/su2/mesh_NACA64A010_inv.su2"
sed -e "s/^TIME_ITER=.*/TIME_ITER= $steps/" -e "s/^CONV_FILENAME=.*/CONV_FILENAME= history_bench/" \
    "$su2_cfg" > "$work/su2/bench.cfg"

results="$work/results.txt"
: > "$results"
echo "== CT5 pitching NACA 64A010, $steps physical steps from the free stream, $rounds rounds alternated ($(nproc --all) cores, $(uname -m))"
for r in $(seq 1 "$rounds"); do
    # MANTA
    l0=$(load)
    out="$work/manta.$r"
    "$timer" -f "%e %U %S %M" -o "$work/manta.$r.time" "$manta" cfd --mesh "$mesh" \
        --motion "$data/ct5_rigid_motion.csv" --config "$data/ct5_rigid.yaml" --out "$out" \
        --max-steps "$steps" --restart > "$work/manta.$r.log" 2>&1 || true
    l1=$(load)
    python3 - "$out/summary.json" "$work/manta.$r.time" "$steps" "$l0" "$l1" >> "$results" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
wall, user, sys_, rss = open(sys.argv[2]).read().split()[-4:]
steps = int(sys.argv[3])
print("manta", float(wall) / steps, (float(user) + float(sys_)) / steps,
      s["inner_iterations_per_step"], sys.argv[4], sys.argv[5], int(rss) / 1024,
      s["seconds_per_step"])
PY
    tail -1 "$results" | awk '{printf "round %s MANTA: %.2f s wall, %.2f s CPU, %.1f inner per step (solve %.2f s wall), load %s -> %s\n", '"$r"', $2, $3, $4, $8, $5, $6}'
    # SU2
    l0=$(load)
    (cd "$work/su2" && rm -f history_bench.csv && "$timer" -f "%e %U %S %M" -o "../su2.$r.time" \
        "$su2" bench.cfg > "../su2.$r.log" 2>&1) || true
    l1=$(load)
    python3 - "$work/su2/history_bench.csv" "$work/su2.$r.time" "$steps" "$l0" "$l1" >> "$results" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
head = [h.strip().strip('"') for h in rows[0]]
body = [[v.strip() for v in r] for r in rows[1:] if r]
it = head.index("Inner_Iter")
steps = int(sys.argv[3])
if len(body) != steps:
    sys.exit(f"SU2 wrote {len(body)} time steps to its history; expected {steps}")
inner = sum(int(r[it]) + 1 for r in body) / len(body)
wall, user, sys_, rss = open(sys.argv[2]).read().split()[-4:]
print("su2", float(wall) / steps, (float(user) + float(sys_)) / steps, inner,
      sys.argv[4], sys.argv[5], int(rss) / 1024)
PY
    tail -1 "$results" | awk '{printf "round %s SU2:   %.2f s wall, %.2f s CPU, %.1f inner per step, load %s -> %s\n", '"$r"', $2, $3, $4, $5, $6}'
done
python3 - "$results" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
cols = ["wall s/step", "CPU s/step", "inner/step", "load before", "load after", "peak MiB",
        "solve wall s/step"]
med = {}
for who in ("manta", "su2"):
    r = [[float(v) for v in x[1:]] for x in rows if x[0] == who]
    if not r:
        continue
    print(f"{who:5s} ({len(r)} runs)  " + "  ".join(
        f"{c} {statistics.median(v[k] for v in r):.3g} [{min(v[k] for v in r):.3g}-{max(v[k] for v in r):.3g}]"
        for k, c in enumerate(cols[:len(r[0])])))
    med[who] = [statistics.median(v[k] for v in r) for k in range(2)]
if len(med) == 2:
    print("ratio MANTA / SU2 of the medians per physical step: wall {:.3f}, CPU {:.3f}".format(
        med["manta"][0] / med["su2"][0], med["manta"][1] / med["su2"][1]))
PY
