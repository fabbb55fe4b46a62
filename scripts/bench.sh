#!/usr/bin/env bash
# `make bench`: every benchmark in bench/, one thread, with the CPU named; then
# the side-by-side comparison with AprilTag 3 and OpenCV ArUco (issue 7), whose
# report.md, PNG figures and frames.csv go to BUILD_DIR/bench-results/.
#
#   scripts/bench.sh [BUILD_DIR] [--quick] [--publish | --publish-only]
#
# --quick         a small comparison (400 frames, well under a minute)
# --publish       also copy the comparison's report and figures to docs/benchmarks/
#                 and its tables into docs/benchmarks.md (between its markers)
# --publish-only  publish the results already in BUILD_DIR/bench-results/, run nothing
# BENCH_LABEL     what is measured, for the report (default: git describe --always --dirty)
set -euo pipefail
build_dir=build
quick=()
publish=0
run=1
for arg in "$@"; do
  case "$arg" in
    --quick) quick=(--quick) ;;
    --publish) publish=1 ;;
    --publish-only) publish=1 run=0 ;;
    -*) echo "bench.sh: unknown option $arg (allowed: --quick, --publish, --publish-only)" >&2; exit 2 ;;
    *) build_dir=$arg ;;
  esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
results=$build_dir/bench-results

if [[ $run == 1 ]]; then
  echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  for bench in "$build_dir"/bench/*_bench; do
    echo "== $(basename "$bench")"
    "$bench" --benchmark_min_time=0.2
  done
  label=${BENCH_LABEL:-$(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)}
  echo "== tag_comparison -> $results/report.md"
  "$build_dir/bench/tag_comparison" "${quick[@]}" --label "$label" --out "$results"
fi

if [[ $publish == 1 ]]; then
  docs=$root/docs
  mkdir -p "$docs/benchmarks"
  cp "$results"/report.md "$results"/*.png "$results"/examples.jpg "$docs/benchmarks"/
  echo "Copied the comparison's report and figures to docs/benchmarks/"
  # The report also goes into docs/benchmarks.md, between these two lines only.
  begin='<!-- tag_comparison results: begin (scripts/bench.sh --publish replaces what follows) -->'
  end='<!-- tag_comparison results: end -->'
  doc=$docs/benchmarks.md
  if grep -qxF "$begin" "$doc" && grep -qxF "$end" "$doc"; then
    report=$(mktemp)
    spliced=$(mktemp)
    sed -E 's#\]\(((fig9|examples)[^)]*)\)#](benchmarks/\1)#g' "$results/report.md" > "$report"
    awk -v begin="$begin" -v end="$end" -v report="$report" '
      $0 == begin { print; while ((getline line < report) > 0) print line; skip = 1; next }
      $0 == end { skip = 0 }
      !skip { print }' "$doc" > "$spliced"
    cat "$spliced" > "$doc"
    rm -f "$report" "$spliced"
    echo "Replaced the results in docs/benchmarks.md"
  else
    echo "docs/benchmarks.md has no results markers; left it alone" >&2
  fi
fi
