#!/usr/bin/env bash
# `make fuzz FUZZ_SECONDS=N`: builds the libFuzzer harnesses of tests/fuzz
# with clang into build-fuzz/ and runs each for N seconds, starting from its
# committed corpus (tests/fuzz/corpus/<name>); new inputs go to
# build-fuzz/corpus/<name>, a crash to build-fuzz/crashes/<name>-*. A crash
# found becomes a regression input: copy it into tests/fuzz/corpus/<name>.
# Exit 1 when a harness finds anything.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${FUZZ_BUILD_DIR:-build-fuzz}
names=(detector palette sidecar calib_sidecar config camera cube image_dpi image_size bundle
  value_parsers print_sidecar sheet_raster locate_sheet video view_selection)

CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCHROMATAG_FUZZ=ON -DCHROMATAG_NATIVE=OFF -DCHROMATAG_BUILD_TESTS=OFF \
  -DCHROMATAG_BUILD_BENCH=OFF -DCHROMATAG_BUILD_PYTHON=OFF >/dev/null
targets=()
for name in "${names[@]}"; do targets+=("fuzz_$name"); done
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

status=0
mkdir -p "$build/crashes"
for name in "${names[@]}"; do
  mkdir -p "$build/corpus/$name"
  echo "fuzz_$name: $seconds s"
  # Leak checks off: Fontconfig and GLib keep caches until exit (cmake/lsan.supp).
  if ! ASAN_OPTIONS=detect_leaks=0 "$build/tests/fuzz/fuzz_$name" -max_total_time="$seconds" \
      -timeout=20 -rss_limit_mb=2560 -print_final_stats=1 \
      -artifact_prefix="$build/crashes/$name-" "$build/corpus/$name" "tests/fuzz/corpus/$name" \
      >"$build/fuzz_$name.log" 2>&1; then
    echo "fuzz_$name FOUND A FAILURE: $build/fuzz_$name.log, $build/crashes/" >&2
    tail -n 30 "$build/fuzz_$name.log" >&2
    status=1
  fi
  grep -E "stat::number_of_executed_units|cov:" "$build/fuzz_$name.log" | tail -n 2 || true
done
# The Python module's array conversions: random arrays from a script (the
# module is the one `make build` made; a crash of the interpreter fails).
python_dir=${CHROMATAG_PYTHON_DIR:-build/python}
# The interpreter the module was built for.
python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' build/CMakeCache.txt 2>/dev/null || true)
python=${python:-/usr/bin/python3}
if ls "$python_dir"/chromatag/_chromatag*.so >/dev/null 2>&1; then
  echo "fuzz_python_arrays: $seconds s"
  if ! PYTHONPATH="$python_dir" "$python" tests/fuzz/fuzz_python_arrays.py "$seconds" \
      >"$build/fuzz_python_arrays.log" 2>&1; then
    echo "fuzz_python_arrays FOUND A FAILURE: $build/fuzz_python_arrays.log" >&2
    tail -n 30 "$build/fuzz_python_arrays.log" >&2
    status=1
  fi
  tail -n 1 "$build/fuzz_python_arrays.log"
else
  echo "fuzz_python_arrays: skipped, no Python module in $python_dir (make build first)"
fi
exit $status
