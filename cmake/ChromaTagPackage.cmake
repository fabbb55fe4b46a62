# The installed package: `cmake --install build --prefix P` puts the CLI, the
# static libraries, their public headers, a relocatable CMake package with
# one component per library (find_package(ChromaTag COMPONENTS detector) ->
# ChromaTag::detector; no components -> all, and ChromaTag::chromatag) and a
# pkg-config file per library (chromatag-detector.pc, ..., chromatag.pc for
# all) under P.
#
# Static libraries, not shared ones: the detector's stages call each other
# thousands of times a frame and are built for this CPU by default
# (CHROMATAG_NATIVE), the toolkit is at 0.x with no ABI to keep stable, and
# the Python module links the same position-independent archives into one
# self-contained extension. The price is that a consumer links our
# dependencies too: ChromaTagConfig.cmake finds those of the components asked
# for (find_dependency, and pkg-config for Cairo, OpenColorIO, GLib, libpng,
# yaml-cpp, tinyxml2, poppler, librsvg and libexif, which ship no CMake package) and the exported
# targets name them.
include(CMakePackageConfigHelpers)

set(CHROMATAG_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ChromaTag)

# ChromaTag::chromatag: every library at once.
get_property(chromatag_libraries GLOBAL PROPERTY CHROMATAG_LIBRARIES)
add_library(chromatag_all INTERFACE)
add_library(ChromaTag::chromatag ALIAS chromatag_all)
target_link_libraries(chromatag_all INTERFACE ${chromatag_libraries})
set_target_properties(chromatag_all PROPERTIES EXPORT_NAME chromatag)
install(TARGETS chromatag_all EXPORT ChromaTag-chromatag-targets)

foreach(target IN LISTS chromatag_libraries ITEMS chromatag_all)
  get_target_property(component ${target} EXPORT_NAME)
  install(EXPORT ChromaTag-${component}-targets NAMESPACE ChromaTag::
          DESTINATION ${CHROMATAG_CMAKE_DIR})
endforeach()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/ChromaTagConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfig.cmake
                              INSTALL_DESTINATION ${CHROMATAG_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfigVersion.cmake
        DESTINATION ${CHROMATAG_CMAKE_DIR})

# pkg-config, one file per library. The archives are static, so each file's
# Requires and Libs carry its dependencies (plain `pkg-config --libs` must
# link) and Requires the ChromaTag libraries it builds on. OpenCV is named
# module by module rather than through opencv4.pc, which links all of
# OpenCV's ~60 libraries. Ceres ships no .pc file; its shared library brings
# its own dependencies.
# The prefix relative to the .pc file's folder, so that the tree can move.
file(RELATIVE_PATH CHROMATAG_PC_UP /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
string(REGEX REPLACE "/$" "" CHROMATAG_PC_UP "${CHROMATAG_PC_UP}")
get_target_property(chromatag_opencv_core opencv_core LOCATION)
get_filename_component(chromatag_opencv_libdir "${chromatag_opencv_core}" DIRECTORY)
set(chromatag_opencv_cflags "")
foreach(dir IN LISTS OpenCV_INCLUDE_DIRS)
  string(APPEND chromatag_opencv_cflags " -I${dir}")
endforeach()
set(chromatag_opencv_libs "")
if(NOT chromatag_opencv_libdir IN_LIST CMAKE_CXX_IMPLICIT_LINK_DIRECTORIES)
  set(chromatag_opencv_libs "-L${chromatag_opencv_libdir} ")
endif()
string(APPEND chromatag_opencv_libs
    "-lopencv_calib3d -lopencv_imgcodecs -lopencv_imgproc -lopencv_core")

function(chromatag_pkg_config name description requires libs cflags)
  set(PC_NAME ${name})
  set(PC_DESCRIPTION "${description}")
  set(PC_REQUIRES "${requires}")
  set(PC_LIBS "${libs}")
  set(PC_CFLAGS "${cflags}")
  configure_file(${PROJECT_SOURCE_DIR}/cmake/chromatag.pc.in ${PROJECT_BINARY_DIR}/${name}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${name}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endfunction()

chromatag_pkg_config(chromatag-base "ChromaTag foundation: input and output files, hashing, units"
                     "glib-2.0" "-lchromatag_base" "")
chromatag_pkg_config(chromatag-families "ChromaTag tag families, palettes and colour maths"
                     "chromatag-base apriltag" "-lchromatag_families" "")
chromatag_pkg_config(chromatag-layout "ChromaTag sheet records and their sidecar files"
                     "chromatag-families" "-lchromatag_layout" "")
chromatag_pkg_config(
  chromatag-generator "ChromaTag tag and sheet generator"
  "chromatag-layout cairo cairo-pdf cairo-svg cairo-png OpenColorIO libpng"
  "-lchromatag_generator" "")
chromatag_pkg_config(chromatag-detector "ChromaTag detector" "chromatag-families nlohmann_json"
                     "-lchromatag_detector ${chromatag_opencv_libs}" "${chromatag_opencv_cflags}")
chromatag_pkg_config(chromatag-rig "ChromaTag camera and board files"
                     "chromatag-layout chromatag-detector yaml-cpp tinyxml2" "-lchromatag_rig" "")
chromatag_pkg_config(chromatag-calib "ChromaTag colour and camera calibration"
                     "chromatag-generator chromatag-rig OpenColorIO cairo"
                     "-lchromatag_calib -lceres" "")
chromatag_pkg_config(chromatag-verify "ChromaTag round-trip and print checks"
                     "chromatag-generator chromatag-detector poppler-cpp librsvg-2.0 cairo libexif" "-lchromatag_verify" "")
chromatag_pkg_config(chromatag "ChromaTag coloured fiducial markers: every library"
                     "chromatag-calib chromatag-verify" "" "")
