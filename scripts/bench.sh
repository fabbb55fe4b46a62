#!/usr/bin/env bash
# `make bench`: every benchmark in bench/, one thread, with the CPU named; then
# the side-by-side comparison with AprilTag 3 and OpenCV ArUco on both data
# sets: "classic" (10,000 frames) into BUILD_DIR/bench-results/classic/
# and "camera" (8,000 frames: 16h5 and 36h11, four prints) into
# BUILD_DIR/bench-results/camera/, each a report.md, PNG figures and frames.csv;
# then camera calibration from a ChromaTag board against OpenCV's ChArUco
# (calib_comparison, 5 trials of 20 views) into
# BUILD_DIR/bench-results/camera-calibration/, a report.md and results.json.
#
#   scripts/bench.sh [BUILD_DIR] [--quick] [--publish | --publish-only]
#
# --quick         small comparisons (400 frames each, 2 calibration trials; about a minute)
# --publish       also copy each comparison's report and figures to docs/benchmarks/
#                 (the camera set's to docs/benchmarks/camera/); the calibration
#                 report to docs/benchmarks/camera-calibration.md. docs/benchmarks.md
#                 quotes the headline figures from these reports, by hand
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
camera_frames=(--frames 8000)
calib_trials=(--trials 5)
if [[ ${#quick[@]} -gt 0 ]]; then
  camera_frames=()
  calib_trials=(--trials 2)
fi

if [[ $run == 1 ]]; then
  echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  for bench in "$build_dir"/bench/*_bench; do
    echo "== $(basename "$bench")"
    "$bench" --benchmark_min_time=0.2
  done
  label=${BENCH_LABEL:-$(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)}
  echo "== tag_comparison --set classic -> $results/classic/report.md"
  "$build_dir/bench/tag_comparison" --set classic "${quick[@]}" --label "$label" \
    --out "$results/classic"
  echo "== tag_comparison --set camera -> $results/camera/report.md"
  "$build_dir/bench/tag_comparison" --set camera "${quick[@]}" "${camera_frames[@]}" \
    --label "$label" --out "$results/camera"
  echo "== calib_comparison -> $results/camera-calibration/report.md"
  "$build_dir/bench/calib_comparison" "${calib_trials[@]}" --label "$label" \
    --out "$results/camera-calibration"
fi

# publish SET DOCS_SUBDIR: copies $results/SET's report and figures to docs/DOCS_SUBDIR.
publish() {
  local set=$1 subdir=$2
  local from=$results/$set to=$root/docs/$subdir
  if [[ ! -f $from/report.md ]]; then
    echo "bench.sh: no $from/report.md; the $set set is not published" >&2
    return
  fi
  mkdir -p "$to"
  cp "$from"/report.md "$from"/*.png "$from"/examples.jpg "$to"/
  echo "Copied the $set comparison's report and figures to docs/$subdir/"
}

# The calibration comparison is a page of its own: its report, as written.
publish_calibration() {
  local from=$results/camera-calibration/report.md to=$root/docs/benchmarks/camera-calibration.md
  if [[ ! -f $from ]]; then
    echo "bench.sh: no $from; the calibration comparison is not published" >&2
    return
  fi
  cp "$from" "$to"
  echo "Copied the calibration comparison's report to docs/benchmarks/camera-calibration.md"
}

if [[ $publish == 1 ]]; then
  publish classic benchmarks
  publish camera benchmarks/camera
  publish_calibration
fi
