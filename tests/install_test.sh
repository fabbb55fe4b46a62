#!/usr/bin/env bash
# The installed package as a user meets it: install the build into a
# temporary prefix and move it (the package must be relocatable); build the
# first program of docs/cpp.md exactly as the page writes it, with
# find_package(ChromaTag COMPONENTS detector) and again with pkg-config, and
# check that a detector-only program neither looks for nor links Ceres,
# Cairo, poppler or the rest; build examples/detect_tags and
# examples/board_pose and run them on a tag and a board the installed CLI
# generated. With the Python module built, also imports it from the
# installed tree.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR LIBDIR [PYTHON PYTHON_DIR]
set -euo pipefail
build=$1
source=$2
libdir=$3
python=${4:-}
python_dir=${5:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/installed" >/dev/null
mv "$work/installed" "$work/prefix"
prefix=$work/prefix

"$prefix/bin/chromatag" generate --ids 3 --one-per-page --dpi 150 -o "$work/tag.png" >/dev/null

# The files docs/cpp.md shows, each after its "<!-- file: PATH -->" line.
mkdir -p "$work/docs"
awk -v out="$work/docs" '
  /^<!-- file: .* -->$/ { file = out "/" $3; system("mkdir -p \"$(dirname " file ")\""); next }
  file != "" && /^```/ { if (open) { close(file); file = ""; open = 0 } else { open = 1; printf "" > file }; next }
  open { print > file }
' "$source/docs/cpp.md"
test -s "$work/docs/first_program/main.cc"
test -s "$work/docs/first_program/CMakeLists.txt"
cmake -S "$work/docs/first_program" -B "$work/first" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/first_configure.txt" 2>&1
if grep -Ei "ceres|metis|suitesparse|glog|cairo|poppler|rsvg|opencolorio" "$work/first_configure.txt"; then
  echo "install_test: configuring a detector-only program looked for the above" >&2
  exit 1
fi
cmake --build "$work/first" >/dev/null
"$work/first/first_program" "$work/tag.png" >"$work/first.txt"
cat "$work/first.txt"
grep -q "^16h5 3 (" "$work/first.txt"
# Direct dependencies only: Debian's OpenCV itself pulls in GDAL and poppler.
if readelf -d "$work/first/first_program" | grep NEEDED | grep -Ei "ceres|cairo|poppler|rsvg|OpenColorIO|yaml|glog"; then
  echo "install_test: a detector-only program links the above" >&2
  exit 1
fi
if "$work/first/first_program" "$work/missing.png" 2>"$work/first_err.txt"; then exit 1; fi
grep -q "cannot read image '$work/missing.png': no such file" "$work/first_err.txt"

# The verify component: the whole dependency chain (Ceres, Cairo, poppler,
# librsvg, libexif) found by the package and by pkg-config, and a generated
# sheet checked through it.
mkdir -p "$work/verify_program"
cat >"$work/verify_program/main.cc" <<'CC'
#include <cstdio>
#include <string>

#include "chromatag/verify/sheet_check.h"

int main(int argc, char** argv) {
  std::string error;
  const auto verdict = chromatag::VerifySheetFile(argv[1], chromatag::VerifyOptions(), &error);
  if (!verdict) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  std::printf("%d of %zu tags pass\n", verdict->tags_passed, verdict->tags.size());
  return verdict->passed ? 0 : 1;
}
CC
printf 'cmake_minimum_required(VERSION 3.22)\nproject(v LANGUAGES CXX)\nfind_package(ChromaTag 0.1 REQUIRED COMPONENTS verify)\nadd_executable(v main.cc)\ntarget_compile_features(v PRIVATE cxx_std_17)\ntarget_link_libraries(v PRIVATE ChromaTag::verify)\n' \
  >"$work/verify_program/CMakeLists.txt"
cmake -S "$work/verify_program" -B "$work/verify_build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/verify_build" >/dev/null
"$work/verify_build/v" "$work/tag.png" | grep -q "^1 of 1 tags pass"

# An unknown component is an error naming the known ones.
mkdir -p "$work/unknown"
printf 'cmake_minimum_required(VERSION 3.22)\nproject(u LANGUAGES CXX)\nfind_package(ChromaTag REQUIRED COMPONENTS detectr)\n' \
  >"$work/unknown/CMakeLists.txt"
if cmake -S "$work/unknown" -B "$work/unknown/build" -DCMAKE_PREFIX_PATH="$prefix" \
  >"$work/unknown.txt" 2>&1; then
  echo "install_test: an unknown component was accepted" >&2
  exit 1
fi
grep -q "no component 'detectr'" "$work/unknown.txt"
# What a detector-only find_package defines: none of the other libraries'
# dependencies (their pkg-config searches are quiet, so the configure output
# alone would not show them). An unknown optional component is passed over.
mkdir -p "$work/probe"
cat >"$work/probe/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(probe LANGUAGES CXX)
find_package(ChromaTag REQUIRED COMPONENTS detector OPTIONAL_COMPONENTS someday)
foreach(target IN ITEMS Ceres::ceres PkgConfig::CAIRO PkgConfig::OCIO PkgConfig::POPPLER_CPP
                        PkgConfig::RSVG PkgConfig::EXIF PkgConfig::YAML_CPP ChromaTag::calib
                        ChromaTag::generator)
  if(TARGET ${target})
    message(FATAL_ERROR "a detector-only find_package defined ${target}")
  endif()
endforeach()
if(NOT TARGET ChromaTag::detector OR NOT TARGET ChromaTag::families OR ChromaTag_someday_FOUND)
  message(FATAL_ERROR "ChromaTag::detector and ::families expected, and no 'someday'")
endif()
CMAKE
cmake -S "$work/probe" -B "$work/probe/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/probe.txt" 2>&1 ||
  { cat "$work/probe.txt"; exit 1; }

cmake -S "$source/examples/detect_tags" -B "$work/example" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/example" >/dev/null
"$work/example/detect_tags" "$work/tag.png" --out "$work/drawn.png" >"$work/cmake.txt"
cat "$work/cmake.txt"
grep -q "^tag 16h5 3 " "$work/cmake.txt"
test -s "$work/drawn.png"

export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig"
# shellcheck disable=SC2046 # pkg-config's flags are meant to split.
g++ -std=c++17 -O1 -o "$work/first_pc" "$work/docs/first_program/main.cc" \
  $(pkg-config --cflags --libs chromatag-detector)
"$work/first_pc" "$work/tag.png" | grep -q "^16h5 3 ("
if pkg-config --libs chromatag-detector | grep -Ei "ceres|cairo|poppler|rsvg|OpenColorIO|opencv_video"; then
  echo "install_test: chromatag-detector.pc links more than the detector needs" >&2
  exit 1
fi
# shellcheck disable=SC2046
g++ -std=c++17 -O1 -o "$work/verify_pc" "$work/verify_program/main.cc" \
  $(pkg-config --cflags --libs chromatag-verify)
"$work/verify_pc" "$work/tag.png" | grep -q "^1 of 1 tags pass"
# The example's camera and window are its own needs, added to the detector's.
# shellcheck disable=SC2046
g++ -std=c++17 -O1 -o "$work/detect_tags_pc" "$source/examples/detect_tags/main.cc" \
  $(pkg-config --cflags --libs chromatag-detector) -lopencv_videoio -lopencv_highgui
"$work/detect_tags_pc" "$work/tag.png" >"$work/pkgconfig.txt"
grep -q "^tag 16h5 3 " "$work/pkgconfig.txt"
# chromatag.pc: every library, and it links.
# shellcheck disable=SC2046
g++ -std=c++17 -O1 -o "$work/first_all" "$work/docs/first_program/main.cc" \
  $(pkg-config --cflags --libs chromatag)
"$work/first_all" "$work/tag.png" | grep -q "^16h5 3 ("
echo "install_test: docs/cpp.md's first program, find_package and pkg-config consumers all found tag 16h5 3"

# The board example: a generated board seen face-on in its own page.
"$prefix/bin/chromatag" generate --board 3x2 --dpi 150 -o "$work/board.png" >/dev/null
cmake -S "$source/examples/board_pose" -B "$work/board_example" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/board_configure.txt" 2>&1
# COMPONENTS rig: the detector's dependencies and yaml-cpp and tinyxml2, no more.
if grep -Ei "ceres|glog|cairo|poppler|rsvg|opencolorio" "$work/board_configure.txt"; then
  echo "install_test: configuring a program on ChromaTag::rig looked for the above" >&2
  exit 1
fi
cmake --build "$work/board_example" >/dev/null
"$work/board_example/board_pose" "$work/board.png" "$work/board.png.json" --focal 1500 \
  --out "$work/board_drawn.png" >"$work/board.txt"
cat "$work/board.txt"
grep -q "^board board.png: 6 of 6 tags" "$work/board.txt"
test -s "$work/board_drawn.png"
# With a camera file (OpenCV's YAML layout) instead of --focal.
printf '%%YAML:1.0\n---\nimage_width: 1240\nimage_height: 1754\ncamera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: [1500, 0, 619.5, 0, 1500, 876.5, 0, 0, 1]\ndistortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 5\n  dt: d\n  data: [0, 0, 0, 0, 0]\n' \
  >"$work/camera.yaml"
"$work/board_example/board_pose" "$work/board.png" "$work/board.png.json" \
  --camera "$work/camera.yaml" | grep -q "^board board.png: 6 of 6 tags"
# Detection, pose, camera files and boards: none of the calibration's,
# generator's or checks' libraries.
if readelf -d "$work/board_example/board_pose" | grep NEEDED |
  grep -Ei "ceres|cairo|poppler|rsvg|OpenColorIO|glog|exif"; then
  echo "install_test: a program using detection, pose, camera and board files links the above" >&2
  exit 1
fi

if [[ -n "$python" ]]; then
  PYTHONPATH="$prefix/$python_dir" "$python" -c "
import sys, cv2, chromatag
assert chromatag.__file__.startswith('$prefix'), chromatag.__file__
found = [(d.family, d.id) for d in chromatag.Detector().detect(cv2.imread(sys.argv[1]))]
assert found == [('16h5', 3)], found
print('install_test: the installed Python module found', found)
" "$work/tag.png"
fi
