#!/usr/bin/env bash
# Run every benchmark executable with repetitions and print the medians.
set -euo pipefail
build=${1:-build}
shopt -s nullglob
found=0
for b in "$build"/bench/*/bench_*; do
    [ -x "$b" ] || continue
    found=1
    echo "== $(basename "$b") ($(nproc) cores, $(uname -m))"
    "$b" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
         --benchmark_display_aggregates_only=true 2>/dev/null | grep -E 'median|Benchmark|----' || true
done
[ -x bench/manoeuvres/run.sh ] && { bash bench/manoeuvres/run.sh "$build" 3; found=1; }
[ $found -eq 1 ] || { echo "no benchmark executables under $build/bench"; exit 1; }
