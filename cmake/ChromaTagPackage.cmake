# The installed package: `cmake --install build --prefix P` puts the CLI, the
# static libraries, their public headers, a relocatable CMake package
# (find_package(ChromaTag) -> ChromaTag::families, ::generator, ::detector,
# ::verify, ::calib and ::chromatag for all) and chromatag.pc under P.
#
# Static libraries, not shared ones: the detector's stages call each other
# thousands of times a frame and are built for this CPU by default
# (CHROMATAG_NATIVE), the toolkit is at 0.x with no ABI to keep stable, and
# the Python module links the same position-independent archives into one
# self-contained extension. The price is that a consumer links our
# dependencies too: ChromaTagConfig.cmake finds them (find_dependency, and
# pkg-config for Cairo, OpenColorIO, GLib, libpng, poppler and librsvg, which ship
# no CMake package) and the exported targets name them.
include(CMakePackageConfigHelpers)

set(CHROMATAG_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ChromaTag)

# ChromaTag::chromatag: every library at once.
get_property(chromatag_libraries GLOBAL PROPERTY CHROMATAG_LIBRARIES)
add_library(chromatag_all INTERFACE)
add_library(ChromaTag::chromatag ALIAS chromatag_all)
target_link_libraries(chromatag_all INTERFACE ${chromatag_libraries})
set_target_properties(chromatag_all PROPERTIES EXPORT_NAME chromatag)
install(TARGETS chromatag_all EXPORT ChromaTagTargets)

install(EXPORT ChromaTagTargets NAMESPACE ChromaTag:: DESTINATION ${CHROMATAG_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/ChromaTagConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfig.cmake
                              INSTALL_DESTINATION ${CHROMATAG_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/ChromaTagConfigVersion.cmake
        DESTINATION ${CHROMATAG_CMAKE_DIR})

# pkg-config: static archives, so the dependencies go in Requires and Libs
# (plain `pkg-config --libs chromatag` must link). Ceres ships no .pc file;
# its shared library brings its own dependencies.
set(CHROMATAG_PC_LIBS "")
foreach(target IN LISTS chromatag_libraries)
  # Dependents before their dependencies, as a static link needs.
  string(PREPEND CHROMATAG_PC_LIBS "-l${target} ")
endforeach()
# The prefix relative to the .pc file's folder, so that the tree can move.
file(RELATIVE_PATH CHROMATAG_PC_UP /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
string(REGEX REPLACE "/$" "" CHROMATAG_PC_UP "${CHROMATAG_PC_UP}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/chromatag.pc.in ${CMAKE_CURRENT_BINARY_DIR}/chromatag.pc
               @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/chromatag.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
