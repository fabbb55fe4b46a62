#!/usr/bin/env bash
# `pip install .` as a Python user runs it, on a copy of the source tree (a
# fresh clone's files: the build writes into its tree): a virtual
# environment that sees Debian's numpy and OpenCV, pip with Debian's
# setuptools and no download, then the installed module imported from the
# environment and run on a tag the CLI generated.
# Usage: pip_install_test.sh SOURCE_DIR PYTHON CLI [BUILD_DIR]
# With BUILD_DIR (the build tree the tests run from), pip configures its
# own tree as a user's install does but packages that tree's module
# (setup.py's CHROMATAG_BUILD_DIR) instead of compiling every library again.
set -euo pipefail
source=$1
python=$2
cli=$3
build=${4:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mkdir "$work/src"
if git -C "$source" rev-parse --git-dir >/dev/null 2>&1; then
  # Tracked and new files as they are in the tree (a tracked file deleted
  # from it is left out).
  git -C "$source" ls-files -z --cached --others --exclude-standard --deduplicate |
    while IFS= read -r -d '' file; do
      if [[ -e "$source/$file" ]]; then printf '%s\0' "$file"; fi
    done | tar -C "$source" --null --no-recursion -T - -cf - | tar -xf - -C "$work/src"
else
  tar -C "$source" --exclude='./build*' -cf - . | tar -xf - -C "$work/src"
fi
test ! -e "$work/src/build"

"$python" -m venv --system-site-packages "$work/venv"
# --no-index: nothing may be downloaded.
CHROMATAG_BUILD_DIR=$build CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-2} \
  "$work/venv/bin/pip" install --no-index --no-build-isolation "$work/src" >"$work/pip.txt" 2>&1 ||
  { tail -40 "$work/pip.txt"; exit 1; }
grep "Successfully installed chromatag-" "$work/pip.txt"

"$cli" generate --ids 3 --one-per-page --dpi 150 -o "$work/tag.png" >/dev/null
cd "$work"  # Not the source tree: the module must come from the environment.
"$work/venv/bin/python" - "$work/tag.png" "$work/venv" "$source" "$build" <<'PY'
import filecmp, glob, os, sys
import cv2
import chromatag

image, venv, source, build = sys.argv[1:]
assert chromatag.__file__.startswith(venv), chromatag.__file__
here = os.path.dirname(chromatag.__file__)
for name in ("py.typed", "__init__.pyi"):
    assert os.path.exists(os.path.join(here, name)), os.listdir(here)
if build:  # The build tree's module, packaged as it is.
    [installed] = glob.glob(os.path.join(here, "_chromatag*.so"))
    [built] = glob.glob(os.path.join(build, "python", "chromatag", "_chromatag*.so"))
    assert filecmp.cmp(installed, built, shallow=False), (installed, built)
found = [(d.family, d.id) for d in chromatag.Detector().detect(cv2.imread(image))]
assert found == [("16h5", 3)], found
# The package's version is the CMake project's.
from importlib.metadata import version
cmake = open(os.path.join(source, "CMakeLists.txt")).read()
assert f"VERSION {version('chromatag')} " in cmake, version("chromatag")
assert chromatag.__version__ == version("chromatag"), chromatag.__version__
print("pip_install_test: chromatag", version("chromatag"), "installed into a venv found", found)
PY
