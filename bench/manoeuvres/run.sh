#!/usr/bin/env bash
# Benchmark of issue 5 (docs/manoeuvres.md#benchmark): minimum time to climb at 40 and 80 LGL
# points, and the Ranger 2000's Immelmann (60 points), Lazy Eight and Barrel Roll (80), each run
# REPS times as a separate `manta optimise` process on one core (OMP/OpenBLAS threads 1).
# Prints, per case, the medians of CPU time and wall time of the solve (from the JSON summary),
# IPOPT iterations, peak resident memory of the process (GNU time), and the final time.
# Usage: bench/manoeuvres/run.sh [BUILD_DIR] [REPS]   (defaults: build, 3)
set -euo pipefail
build=${1:-build}
reps=${2:-3}
root=$(cd "$(dirname "$0")/../.." && pwd)
manta="$build/bin/manta"
[ -x "$manta" ] || { echo "no $manta"; exit 1; }
command -v python3 > /dev/null || { echo "python3 is needed for the medians"; exit 1; }
timer=/usr/bin/time
[ -x "$timer" ] || { echo "GNU time (/usr/bin/time) is needed for the peak memory"; exit 1; }
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ranger="$root/examples/ranger2000"
cases=(
    "climb-40|--problem min-time-to-climb --nodes 40"
    "climb-80|--problem min-time-to-climb --nodes 80"
    "immelmann-60|--aircraft $ranger/aircraft.yaml --manoeuvre $ranger/manoeuvres/immelmann.yaml"
    "lazy_eight-80|--aircraft $ranger/aircraft.yaml --manoeuvre $ranger/manoeuvres/lazy_eight.yaml"
    "barrel_roll-80|--aircraft $ranger/aircraft.yaml --manoeuvre $ranger/manoeuvres/barrel_roll.yaml"
)
echo "== manoeuvres benchmark ($(nproc --all) cores, $(uname -m), $reps repetitions, medians)"
for c in "${cases[@]}"; do
    name=${c%%|*}
    args=${c#*|}
    for r in $(seq 1 "$reps"); do
        # shellcheck disable=SC2086
        taskset -c 0 "$timer" -f "%M" -o "$work/$name.$r.mem" "$manta" optimise $args --json \
            > "$work/$name.$r.json" 2> /dev/null || true
    done
    python3 - "$work" "$name" "$reps" <<'PY'
import json, statistics, sys
work, name, reps = sys.argv[1], sys.argv[2], int(sys.argv[3])
rows = []
for r in range(1, reps + 1):
    try:
        j = json.load(open(f"{work}/{name}.{r}.json"))
        mem = int(open(f"{work}/{name}.{r}.mem").read().split()[-1]) / 1024.0
    except (OSError, ValueError, IndexError):
        continue
    rows.append((j["cpu_time"], j["wall_time"], j["iterations"], mem, j["final_time"], j["converged"]))
if not rows:
    print(f"{name:16s} failed")
    sys.exit(0)
med = lambda k: statistics.median(r[k] for r in rows)
ok = all(r[5] for r in rows)
print(f"{name:16s} cpu {med(0):8.2f} s  wall {med(1):8.2f} s  iterations {med(2):5.0f}  "
      f"peak memory {med(3):7.1f} MiB  final time {med(4):.4f} s{'' if ok else '  (NOT converged)'}")
PY
done
