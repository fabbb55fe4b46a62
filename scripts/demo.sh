#!/usr/bin/env bash
# `make demo`: the main job on built-in defaults. Writes a print-ready sheet of
# every kept 16h5 ID into demo-output/ and summarises the families and
# palettes. Issue 5 extends it into generate -> verify.
set -euo pipefail
chromatag=${1:-build/cli/chromatag}
out=${2:-demo-output}
mkdir -p "$out"
"$chromatag" --version
echo
"$chromatag" families --family 16h5
echo
"$chromatag" palettes --palette default
echo
"$chromatag" generate --family 16h5 --all --size 40mm --page a4 -o "$out/chromatag-16h5.pdf"
echo
echo "Print $out/chromatag-16h5.pdf at 100 % (no fit to page); $out/chromatag-16h5.json records"
echo "where each tag is on the page."
