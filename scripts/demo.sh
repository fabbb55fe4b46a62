#!/usr/bin/env bash
# `make demo`: the main job on built-in defaults. Until the generator and the
# detector land (issues 3 and 4) that is the family and palette summaries.
set -euo pipefail
chromatag=${1:-build/cli/chromatag}
"$chromatag" --version
echo
"$chromatag" families
echo
"$chromatag" palettes
