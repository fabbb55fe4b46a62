# Small helpers in the spirit of COLMAP's: one call per library, test or tool.

set(CHROMATAG_WARNINGS -Wall -Wextra -Wpedantic)

# Code generation. CHROMATAG_NATIVE builds for the CPU that compiles (as
# llama.cpp's GGML_NATIVE does): the scalar parts of the detector's stages
# then use the newer instructions too. Packagers building for other machines
# turn it off. In both builds the vector kernels (detector/src/kernels) are
# chosen at run time, once per detector, by what the CPU has.
# Floating-point contraction stays off either way, so that a native and a
# portable build give the same detections to the last bit (fused
# multiply-adds round differently).
set(CHROMATAG_CODEGEN_FLAGS -ffp-contract=off)
if(CHROMATAG_NATIVE)
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag(-march=native CHROMATAG_HAVE_MARCH_NATIVE)
  if(CHROMATAG_HAVE_MARCH_NATIVE)
    list(APPEND CHROMATAG_CODEGEN_FLAGS -march=native)
  endif()
endif()

function(chromatag_target_defaults target)
  target_compile_options(${target} PRIVATE ${CHROMATAG_WARNINGS} ${CHROMATAG_CODEGEN_FLAGS})
  if(CHROMATAG_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  # float-cast-overflow: not part of GCC's "undefined" (clang's has it), and
  # the casts of out-of-range numbers must be caught too.
  if(CHROMATAG_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined,float-cast-overflow
                                             -fno-omit-frame-pointer -fno-sanitize-recover=all)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined,float-cast-overflow)
  endif()
  if(CHROMATAG_TSAN)
    target_compile_options(${target} PRIVATE -fsanitize=thread -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=thread)
  endif()
  # The fuzzers' coverage in every library they reach.
  if(CHROMATAG_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link,address,undefined,float-cast-overflow
                                             -fno-sanitize-recover=all)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined,float-cast-overflow)
  endif()
endfunction()

# chromatag_add_library(NAME families SRCS a.cc b.cc [INTERNAL]
#                       PUBLIC_LINK_LIBS ... PRIVATE_LINK_LIBS ...)
# defines the target chromatag_<NAME> and its alias ChromaTag::<NAME>, with
# <NAME>/include as its public include folder. INTERNAL libraries (the
# benchmark's) are not installed.
function(chromatag_add_library)
  cmake_parse_arguments(ARG "INTERNAL" "NAME" "SRCS;PUBLIC_LINK_LIBS;PRIVATE_LINK_LIBS" ${ARGN})
  set(target chromatag_${ARG_NAME})
  add_library(${target} STATIC ${ARG_SRCS})
  add_library(ChromaTag::${ARG_NAME} ALIAS ${target})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_LINK_LIBS} PRIVATE ${ARG_PRIVATE_LINK_LIBS})
  # Position-independent, so that the Python module can link the same archives.
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME ${ARG_NAME})
  chromatag_target_defaults(${target})
  if(ARG_INTERNAL)
    return()
  endif()
  # Installed as ChromaTag::<NAME>, one export file per library, so that a
  # program asking for one component loads only what it needs
  # (cmake/ChromaTagPackage.cmake).
  install(TARGETS ${target} EXPORT ChromaTag-${ARG_NAME}-targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
          FILES_MATCHING PATTERN "*.h")
  set_property(GLOBAL APPEND PROPERTY CHROMATAG_LIBRARIES ${target})
endfunction()

# chromatag_add_test(NAME families_test SRCS a_test.cc LINK_LIBS ...)
function(chromatag_add_test)
  if(NOT CHROMATAG_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "NAME" "SRCS;LINK_LIBS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LINK_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${ARG_NAME} PRIVATE
    CHROMATAG_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    CHROMATAG_TEST_DATA_DIR="${PROJECT_SOURCE_DIR}/tests/data")
  chromatag_target_defaults(${ARG_NAME})
  gtest_discover_tests(${ARG_NAME} DISCOVERY_TIMEOUT 60
                       WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endfunction()

# chromatag_add_executable(NAME chromatag SRCS main.cc LINK_LIBS ...)
function(chromatag_add_executable)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;LINK_LIBS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LINK_LIBS})
  chromatag_target_defaults(${ARG_NAME})
endfunction()
