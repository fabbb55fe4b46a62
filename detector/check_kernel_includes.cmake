# Run as a test (detector/CMakeLists.txt): cmake -DKERNELS_DIR=<dir> -P this.
#
# The vector kernels know no stage (src/kernels/kernels.h): their interface
# is plain data, so that a kernel can be read, tested and moved on its own.
# Fails when a file in KERNELS_DIR includes a header of the project other
# than the kernels' own ("kernels/...") and the families' ("chromatag/
# families/..."); system, OpenCV and test framework headers are free.
if(NOT KERNELS_DIR OR NOT IS_DIRECTORY "${KERNELS_DIR}")
  message(FATAL_ERROR "KERNELS_DIR (${KERNELS_DIR}) is not a folder")
endif()
file(GLOB files "${KERNELS_DIR}/*.h" "${KERNELS_DIR}/*.cc")
if(NOT files)
  message(FATAL_ERROR "no sources in ${KERNELS_DIR}")
endif()
set(bad "")
foreach(file IN LISTS files)
  file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]")
  get_filename_component(name "${file}" NAME)
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*([\"<])([^\">]*)[\">].*$" "\\1;\\2" parts
                         "${line}")
    list(GET parts 0 quote)
    list(GET parts 1 header)
    if(header MATCHES "^kernels/[^/]+$" OR header MATCHES "^chromatag/families/")
      continue()
    endif()
    # Quoted: the project's own headers; angle brackets: the project's
    # installed ones are named chromatag/...
    if(quote STREQUAL "\"" OR header MATCHES "^chromatag/")
      string(APPEND bad "\n  ${name}: ${line}")
    endif()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "kernels include headers outside src/kernels (pass plain data instead):${bad}")
endif()
list(LENGTH files count)
message(STATUS "${count} kernel files include only kernels, families, system and OpenCV headers")
