#!/usr/bin/env bash
# Benchmark of issue 20 (docs/performance.md#optimal-control-against-psopt): MANTA's optimal-control
# library against PSOPT 5.0.2 on the same problems, the same IPOPT (the system's, MUMPS), the same
# tolerance (tol 1e-8), exact Hessians (PSOPT: ADOL-C; on the climb PSOPT's example's own finite
# differences and so IPOPT's limited-memory Hessian, see below), one LGL segment of the same number
# of points per phase as
# the starting mesh, the same starting guesses, and each tool's own mesh refinement from a coarse
# mesh (MANTA: solve_adaptive with its default options, tolerance 1e-6; PSOPT:
# mesh_refinement = "automatic", ode_tolerance 1e-6, at most 10 passes).
#
# Problems: PSOPT's own examples brac1 (brachistochrone to (2, 2), g = 9.8), climb (Bryson's
# minimum time to climb) and twophase_schwartz, compiled from PSOPT's source tree into the work
# folder (never into the repository) after three edits to a copy: the settings above are set
# just before the call to psopt(), one result line is printed after it (the plots are skipped),
# and climb.cxx's atmosphere layer search `while (j<=i+1)`, which never runs, becomes
# `while (j>i+1)` so that both tools solve the problem with the 8-layer atmosphere whose optimum
# PSOPT documents (321.11 s). On the climb PSOPT keeps its example's derivatives = "numerical":
# ADOL-C tapes once, and with "automatic" the branches of the tables and the atmosphere abort its
# forward sweeps ("Branch switch detected") and IPOPT ends in restoration. MANTA:
# build/bench/optimal/bench_optimal_vs_psopt (bench/optimal/vs_psopt.cpp).
#
# Runs alternate (MANTA PSOPT MANTA PSOPT ...) for ROUNDS rounds per case. Per run: wall and CPU
# time (user + system) of the whole process (GNU time; start-up included), the solver's own CPU
# time (MANTA: the solves; PSOPT: the NLP solves of its mesh statistics), IPOPT iterations (all
# passes), passes, final LGL points, the optimum and its error to the published value, and the
# load average (1 min) before and after. Prints the medians and the spread (min-max).
#
# Usage: bench/optimal/vs_psopt.sh [--rounds N] [--build DIR] [--psopt PREFIX] [--psopt-src DIR]
#                                  [--adolc PREFIX] [--cases "problem:mode:nodes ..."]
#                                  [--work DIR] [--keep]
# Defaults: 3 rounds; build; PSOPT installed in $PSOPT_PREFIX or /work/peers/psopt (lib/PSOPT,
# include/PSOPT), its source tree (for the examples) in $PSOPT_SRC or /work/peers/psopt-src;
# ADOL-C 2.7.2 built with ColPack's sparse drivers in $ADOLC_PREFIX or /work/peers/adolc
# (Debian's libadolc2 is built without ColPack, and PSOPT's exact derivatives need sparse_jac);
# cases "brachistochrone:fixed:40 brachistochrone:adaptive:10 climb:fixed:40 climb:adaptive:10
# schwartz:fixed:40 schwartz:adaptive:10" (nodes per phase); a temporary folder (removed unless
# --keep; with --work the compiled PSOPT examples are kept and reused).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
rounds=3
build="$root/build"
psopt=${PSOPT_PREFIX:-/work/peers/psopt}
psopt_src=${PSOPT_SRC:-/work/peers/psopt-src}
adolc=${ADOLC_PREFIX:-/work/peers/adolc}
cases="brachistochrone:fixed:40 brachistochrone:adaptive:10 climb:fixed:40 climb:adaptive:10 schwartz:fixed:40 schwartz:adaptive:10"
work=""
keep=0
while [ $# -gt 0 ]; do
    case "$1" in
        --rounds) rounds=$2; shift 2 ;;
        --build) build=$2; shift 2 ;;
        --psopt) psopt=$2; shift 2 ;;
        --psopt-src) psopt_src=$2; shift 2 ;;
        --adolc) adolc=$2; shift 2 ;;
        --cases) cases=$2; shift 2 ;;
        --work) work=$2; shift 2 ;;
        --keep) keep=1; shift ;;
        *) echo "vs_psopt.sh: unknown argument '$1'; expected --rounds, --build, --psopt, --psopt-src, --adolc, --cases, --work or --keep" >&2; exit 2 ;;
    esac
done
manta="$build/bin/bench_optimal_vs_psopt"
[ -x "$manta" ] || manta="$build/bench/optimal/bench_optimal_vs_psopt"
timer=/usr/bin/time
for f in "$manta" "$timer"; do
    [ -x "$f" ] || { echo "vs_psopt.sh: $f is not an executable (build the target bench_optimal_vs_psopt)" >&2; exit 1; }
done
lib="$psopt/lib/PSOPT/libPSOPT.a"
[ -f "$lib" ] || { echo "vs_psopt.sh: no PSOPT library $lib (--psopt PREFIX: PSOPT's install prefix)" >&2; exit 1; }
[ -f "$psopt/include/PSOPT/psopt.h" ] || { echo "vs_psopt.sh: no $psopt/include/PSOPT/psopt.h" >&2; exit 1; }
for e in brac1 climb twophase_schwartz; do
    [ -f "$psopt_src/examples/$e/$e.cxx" ] || { echo "vs_psopt.sh: no PSOPT example $psopt_src/examples/$e/$e.cxx (--psopt-src DIR)" >&2; exit 1; }
done
command -v python3 > /dev/null || { echo "vs_psopt.sh: python3 is needed for the medians" >&2; exit 1; }
pkg-config --exists ipopt eigen3 || { echo "vs_psopt.sh: pkg-config does not find ipopt and eigen3" >&2; exit 1; }
adolc_lib=$(ls -d "$adolc"/lib64 "$adolc"/lib 2>/dev/null | head -n 1 || true)
[ -f "$adolc/include/adolc/adolc.h" ] && [ -n "$adolc_lib" ] ||
    { echo "vs_psopt.sh: no ADOL-C in $adolc (--adolc PREFIX: include/adolc/adolc.h, lib64 or lib)" >&2; exit 1; }
for c in $cases; do
    IFS=: read -r problem mode nodes <<< "$c"
    case "$problem" in brachistochrone|climb|schwartz) ;; *) echo "vs_psopt.sh: case '$c': problem '$problem', expected brachistochrone, climb or schwartz" >&2; exit 2 ;; esac
    case "$mode" in fixed|adaptive) ;; *) echo "vs_psopt.sh: case '$c': mode '$mode', expected fixed or adaptive" >&2; exit 2 ;; esac
    [[ "$nodes" =~ ^[0-9]+$ ]] && [ "$nodes" -ge 2 ] || { echo "vs_psopt.sh: case '$c': nodes '$nodes', expected an integer >= 2" >&2; exit 2; }
done
if [ -z "$work" ]; then
    work=$(mktemp -d)
    [ "$keep" = 1 ] || trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work/bin" "$work/run"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
load() { cut -d' ' -f1 /proc/loadavg; }

example_of() {
    case "$1" in
        brachistochrone) echo brac1 ;;
        climb) echo climb ;;
        schwartz) echo twophase_schwartz ;;
        *) echo "vs_psopt.sh: case problem '$1', expected brachistochrone, climb or schwartz" >&2; exit 2 ;;
    esac
}

# One PSOPT executable per (problem, mode, nodes): a copy of the example with the settings set
# before psopt() and a result line after it.
psopt_exe() {
    local problem=$1 mode=$2 nodes=$3
    local ex; ex=$(example_of "$problem")
    local exe="$work/bin/${ex}_${mode}_${nodes}"
    if [ ! -x "$exe" ] || [ "$psopt_src/examples/$ex/$ex.cxx" -nt "$exe" ] || [ "$0" -nt "$exe" ]; then
        local refine=manual
        [ "$mode" = adaptive ] && refine=automatic
        # climb: PSOPT's example's own "numerical" (ADOL-C tapes once; with "automatic" the
        # table and atmosphere branches abort the forward sweeps and IPOPT ends in restoration)
        local derivatives=automatic
        [ "$problem" = climb ] && derivatives=numerical
        local set="algorithm.collocation_method = \"Legendre\"; algorithm.derivatives = \"$derivatives\"; algorithm.hessian = \"exact\"; algorithm.nlp_tolerance = 1.e-8; algorithm.nlp_iter_max = 3000; algorithm.ipopt_linear_solver = \"mumps\"; algorithm.mesh_refinement = \"$refine\"; algorithm.ode_tolerance = 1.e-6; algorithm.mr_max_iterations = 10; for (int bench_ph = 1; bench_ph <= problem.nphases; ++bench_ph) { problem.phases(bench_ph).nodes.resize(1); problem.phases(bench_ph).nodes(0) = $nodes; }"
        local report="{ int bench_np = algorithm.mesh_refinement == \"automatic\" ? algorithm.mr_max_iterations : 1; printf(\"\\\\nPSOPT_RESULT cost=%.12g code=%d error_flag=%d cpu=%.6g\", solution.cost, solution.nlp_return_code, solution.error_flag, solution.cpu_time); for (int bench_k = 0; bench_k < bench_np; ++bench_k) printf(\" mesh%d=%d,%.6g,%.3e\", bench_k + 1, solution.mesh_stats[bench_k].nnodes, solution.mesh_stats[bench_k].CPU_time, solution.mesh_stats[bench_k].epsilon_max); printf(\"\\\\n\"); return 0; }"
        local src="$work/bin/${ex}_${mode}_${nodes}.cxx"
        grep -q '^ *psopt(solution, problem, algorithm);' "$psopt_src/examples/$ex/$ex.cxx" ||
            { echo "vs_psopt.sh: no line 'psopt(solution, problem, algorithm);' in $ex.cxx" >&2; exit 1; }
        sed -e "s|^\( *\)psopt(solution, problem, algorithm);|\1$set\n\1psopt(solution, problem, algorithm);\n\1$report|" \
            -e 's|while (j<=i+1) {|while (j>i+1) {|' "$psopt_src/examples/$ex/$ex.cxx" > "$src"
        # shellcheck disable=SC2046
        nice -n 19 g++ -O3 -DNDEBUG -DHAVE_CSTDDEF -std=c++17 -w -I"$psopt/include/PSOPT" \
            -I"$adolc/include" $(pkg-config --cflags eigen3 ipopt) "$src" -o "$exe" "$lib" \
            -L"$adolc_lib" -Wl,-rpath,"$adolc_lib" -ladolc -lColPack $(pkg-config --libs ipopt) >&2 ||
            { echo "vs_psopt.sh: compiling $src failed" >&2; exit 1; }
    fi
    echo "$exe"
}

# published optima
reference() {
    case "$1" in
        brachistochrone) python3 - <<'PY'
import math
# cycloid through (2, 2) from rest, g = 9.8: (phi - sin phi) / (1 - cos phi) = x_f / y_f
f = lambda p: (p - math.sin(p)) / (1 - math.cos(p)) - 1.0
a, b = 1e-3, 2 * math.pi - 1e-3
for _ in range(200):
    m = 0.5 * (a + b)
    a, b = (a, m) if f(a) * f(m) <= 0 else (m, b)
phi = 0.5 * (a + b)
R = 2.0 / (1 - math.cos(phi))
print(repr(phi * math.sqrt(R / 9.8)))
PY
        ;;
        climb) echo 321.11 ;;       # PSOPT's documented t_f (its manual), 8-layer atmosphere
        schwartz) echo 0 ;;         # J* = 0: the second phase reaches the origin (PSOPT: 4.6e-15)
    esac
}

results="$work/results.txt"
: > "$results"
echo "== MANTA against PSOPT $(basename "$psopt_src"), $rounds rounds alternated per case ($(nproc --all) cores, $(uname -m), load $(load))"
for c in $cases; do
    IFS=: read -r problem mode nodes <<< "$c"
    ref=$(reference "$problem")
    exe=$(psopt_exe "$problem" "$mode" "$nodes") || exit 1
    for _ in $(seq 1 "$rounds"); do
        # MANTA
        l0=$(load)
        "$timer" -f "%e %U %S" -o "$work/manta.time" "$manta" "$problem" "$mode" "$nodes" > "$work/manta.log" 2>&1 || true
        l1=$(load)
        python3 - "$work/manta.log" "$work/manta.time" "$c" "$ref" "$l0" "$l1" >> "$results" <<'PY'
import sys
line = [l for l in open(sys.argv[1]) if l.startswith("manta ")]
if not line:
    sys.exit("MANTA wrote no result line: " + open(sys.argv[1]).read()[-400:])
kv = dict(f.split("=", 1) for f in line[-1].split()[1:])
wall, user, sys_ = open(sys.argv[2]).read().split()[-3:]
obj = float(kv["objective"])
print("manta", sys.argv[3], kv["status"], float(wall), float(user) + float(sys_),
      kv["solve_cpu_s"], kv["iterations"], kv["passes"], kv["nodes"], repr(obj),
      obj - float(sys.argv[4]), sys.argv[5], sys.argv[6], kv["node_list"], kv["max_error"])
PY
        tail -n 1 "$results" | awk '{printf "%s MANTA: %s, %.3f s wall, %.3f s CPU (solve %s), %s IPOPT it, %s passes, %s points (%s, estimate %s), %s (error %.2e), load %s -> %s\n", $2, $3, $4, $5, $6, $7, $8, $9, $14, $15, $10, $11, $12, $13}'
        # PSOPT
        l0=$(load)
        (cd "$work/run" && "$timer" -f "%e %U %S" -o "../psopt.time" "$exe" > "../psopt.log" 2>&1) || true
        l1=$(load)
        python3 - "$work/psopt.log" "$work/psopt.time" "$c" "$ref" "$l0" "$l1" >> "$results" <<'PY'
import re, sys
text = open(sys.argv[1], errors="replace").read()
line = [l for l in text.splitlines() if l.startswith("PSOPT_RESULT")]
if not line:
    sys.exit("PSOPT wrote no result line: " + text[-400:])
f = line[-1].split()
kv = dict(x.split("=", 1) for x in f[1:] if not x.startswith("mesh"))
its = [int(m) for m in re.findall(r"Number of Iterations\.*: *(\d+)", text)]
exits = re.findall(r"EXIT: *(.*)", text)
passes = len(its)
mesh = [tuple(x.split("=", 1)[1].split(",")) for x in f[1:] if x.startswith("mesh")][:passes]
nodes = int(mesh[-1][0]) if mesh else 0
nlp_cpu = sum(float(m[1]) for m in mesh)
status = "solved" if exits and exits[-1].startswith("Optimal Solution Found") else (
    "acceptable" if exits and "Acceptable" in exits[-1] else "failed")
# the refinement's stop: the last pass's ODE error against ode_tolerance (1e-6), else 10 passes
err = float(mesh[-1][2]) if mesh else -1.0
if sys.argv[3].split(":")[1] == "adaptive":
    status += ",tolerance_met" if 0 <= err <= 1e-6 else (",pass_limit" if passes >= 10 else ",stopped")
else:
    err = -1.0
wall, user, sys_ = open(sys.argv[2]).read().split()[-3:]
obj = float(kv["cost"])
print("psopt", sys.argv[3], status, float(wall), float(user) + float(sys_), f"{nlp_cpu:.4f}",
      sum(its), passes, nodes, repr(obj), obj - float(sys.argv[4]), sys.argv[5], sys.argv[6],
      ",".join(m[0] for m in mesh), f"{err:.3e}")
PY
        tail -n 1 "$results" | awk '{printf "%s PSOPT: %s, %.3f s wall, %.3f s CPU (NLP %s), %s IPOPT it, %s passes, %s points (%s, estimate %s), %s (error %.2e), load %s -> %s\n", $2, $3, $4, $5, $6, $7, $8, $9, $14, $15, $10, $11, $12, $13}'
    done
done
echo "== medians [min-max] per case"
python3 - "$results" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
cases = []
for r in rows:
    if r[1] not in cases:
        cases.append(r[1])
def span(v, fmt):
    return f"{statistics.median(v):{fmt}} [{min(v):{fmt}}-{max(v):{fmt}}]"
print("| case | tool | status | wall s | CPU s | solver CPU s | IPOPT it | passes | points | last error estimate | optimum | error to published | load |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for c in cases:
    med = {}
    for who in ("manta", "psopt"):
        r = [x for x in rows if x[0] == who and x[1] == c]
        if not r:
            continue
        col = lambda k: [float(x[k]) for x in r]
        status = ",".join(sorted(set(x[2] for x in r)))
        its = sorted(set(x[6] for x in r))
        pts = sorted(set(x[8] for x in r))
        opt = sorted(set(x[9] for x in r))
        err = statistics.median(col(10))
        load = f"{min(col(11) + col(12)):.1f}-{max(col(11) + col(12)):.1f}"
        print(f"| {c} | {who} | {status} | {span(col(3), '.3f')} | {span(col(4), '.3f')} | "
              f"{span(col(5), '.3f')} | {'/'.join(its)} | {r[0][7]} | {'/'.join(pts)} "
              f"({r[-1][13]}) | {r[-1][14] if float(r[-1][14]) >= 0 else '-'} | {float(opt[0]):.10g} | {err:.2e} | {load} |")
        med[who] = statistics.median(col(4))
    if len(med) == 2 and med["psopt"] > 0:
        print(f"| {c} | ratio MANTA / PSOPT of the median CPU | {med['manta'] / med['psopt']:.3f} | | | | | | | | | | |")
PY
