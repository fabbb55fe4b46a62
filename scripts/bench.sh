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
  docs=$(dirname "$0")/../docs
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
