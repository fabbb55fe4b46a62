#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages the project builds, tests and runs with.
# Quick and silent when everything is present; otherwise apt-get (through sudo
# when not root). Used by `make demo`, `make test` and CI.
set -euo pipefail

packages=(
  # Toolchain.
  g++ cmake ninja-build pkg-config make git
  # The formatter the tree is checked with (make format; the clang_format test).
  clang-format-14
  # Libraries (brief: Cairo, OpenCV, Eigen, Ceres, OpenColorIO, CLI11,
  # libapriltag, nlohmann-json, poppler).
  libapriltag-dev libcairo2-dev libopencv-dev libopencv-contrib-dev libeigen3-dev libceres-dev
  libopencolorio-dev libcli11-dev nlohmann-json3-dev libpoppler-cpp-dev librsvg2-dev libglib2.0-dev libpng-dev zlib1g-dev
  # Camera files (ROS camera_info, Kalibr, OpenCV YAML) for detect --camera.
  libyaml-cpp-dev
  # OpenCV's XML camera files.
  libtinyxml2-dev
  # The resolution in a JPEG scan's EXIF (verify --print --scan).
  libexif-dev
  # Fonts for the labels and notes on generated sheets.
  fonts-dejavu-core
  # The Python module (pybind11 on numpy) and its tests (cv2 reads images in them).
  pybind11-dev python3-dev python3-numpy python3-pytest python3-opencv
  # Tests and benchmarks (libopencv-contrib-dev above: ArUco, for the comparison).
  libgtest-dev libgmock-dev libbenchmark-dev
  # A real printer in the tests: LittleCMS applies Ghostscript's SWOP press
  # profile (default_cmyk.icc, in libgs-common) to pages before they are
  # photographed or scanned.
  liblcms2-dev libgs-common
  # Natural photographs for the no-false-detection tests and the benchmark.
  opencv-doc
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  if ! command -v sudo >/dev/null; then
    echo "install-deps: not root and no sudo; install these packages: ${missing[*]}" >&2
    exit 1
  fi
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q >&2
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
