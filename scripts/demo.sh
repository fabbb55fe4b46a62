#!/usr/bin/env bash
# `make demo`: the main job on built-in defaults. Generates a print-ready
# sheet of every kept 16h5 ID into demo-output/, verifies it by rasterising
# the PDF and detecting every tag again, and prints the summary.
set -euo pipefail
chromatag=${1:-build/cli/chromatag}
out=${2:-demo-output}
mkdir -p "$out"
sheet="$out/chromatag-16h5.pdf"
"$chromatag" --version
echo
"$chromatag" generate --family 16h5 --all --size 40mm --page a4 -o "$sheet"
echo
"$chromatag" verify "$sheet"
echo
echo "Print $sheet at 100 % (no fit to page) and check the scale bar;"
echo "${sheet}.json records where each tag is on the page."
