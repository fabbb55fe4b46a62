#!/usr/bin/env bash
# `make bench`: every benchmark in bench/, one thread, with the CPU named; then
# the side-by-side comparison with AprilTag 3 and OpenCV ArUco (issue 7), whose
# report.md, PNG figures and frames.csv go to BUILD_DIR/bench-results/.
#
#   scripts/bench.sh [BUILD_DIR] [--quick] [--publish]
#
# --quick    a small comparison (400 frames, well under a minute)
# --publish  also copy the comparison's report and figures to docs/benchmarks/
set -euo pipefail
build_dir=build
quick=()
publish=0
for arg in "$@"; do
  case "$arg" in
    --quick) quick=(--quick) ;;
    --publish) publish=1 ;;
    -*) echo "bench.sh: unknown option $arg (allowed: --quick, --publish)" >&2; exit 2 ;;
    *) build_dir=$arg ;;
  esac
done
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
for bench in "$build_dir"/bench/*_bench; do
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.2
done

results=$build_dir/bench-results
echo "== tag_comparison -> $results/report.md"
"$build_dir/bench/tag_comparison" "${quick[@]}" --out "$results"
if [[ $publish == 1 ]]; then
  docs=$(dirname "$0")/../docs/benchmarks
  mkdir -p "$docs"
  cp "$results"/report.md "$results"/*.png "$results"/examples.jpg "$docs"/
  echo "Copied the comparison's report and figures to docs/benchmarks/"
fi
