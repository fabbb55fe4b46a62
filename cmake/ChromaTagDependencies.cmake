# Every dependency comes from Debian's packages; scripts/install-deps.sh installs them.
find_package(PkgConfig REQUIRED)
find_package(apriltag REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs calib3d videoio highgui objdetect)
find_package(Eigen3 REQUIRED NO_MODULE)
find_package(Ceres REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(Threads REQUIRED)
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo cairo-pdf cairo-svg cairo-png)
# OpenColorIO through pkg-config: Debian 12's CMake config for it computes its
# prefix as "/" and names a missing /include.
pkg_check_modules(OCIO REQUIRED IMPORTED_TARGET OpenColorIO)
# GLib's SHA-256 and libpng's encoder (both already there through Cairo).
pkg_check_modules(GLIB REQUIRED IMPORTED_TARGET glib-2.0)
pkg_check_modules(PNG REQUIRED IMPORTED_TARGET libpng)
# zlib's crc32, for the tests' hand-made PNG headers.
pkg_check_modules(ZLIB REQUIRED IMPORTED_TARGET zlib)
# Camera files for `detect --camera` (ROS camera_info, Kalibr and OpenCV YAML).
pkg_check_modules(YAML_CPP REQUIRED IMPORTED_TARGET yaml-cpp)
# OpenCV's XML camera files: a real parser (comments, CDATA, entities).
pkg_check_modules(TINYXML2 REQUIRED IMPORTED_TARGET tinyxml2)
pkg_check_modules(POPPLER_CPP REQUIRED IMPORTED_TARGET poppler-cpp)
if(CHROMATAG_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(CHROMATAG_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
