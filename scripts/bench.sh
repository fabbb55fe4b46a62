#!/usr/bin/env bash
# `make bench`: every benchmark in bench/, one thread, with the CPU named.
set -euo pipefail
build_dir=${1:-build}
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
for bench in "$build_dir"/bench/*_bench; do
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.2
done
