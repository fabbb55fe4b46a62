# Small helpers in the spirit of COLMAP's: one call per library, test or tool.

set(CHROMATAG_WARNINGS -Wall -Wextra -Wpedantic)

function(chromatag_target_defaults target)
  target_compile_options(${target} PRIVATE ${CHROMATAG_WARNINGS})
  if(CHROMATAG_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(CHROMATAG_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# chromatag_add_library(NAME families SRCS a.cc b.cc
#                       PUBLIC_LINK_LIBS ... PRIVATE_LINK_LIBS ...)
# defines the target chromatag_<NAME> and its alias ChromaTag::<NAME>, with
# <NAME>/include as its public include folder.
function(chromatag_add_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;PUBLIC_LINK_LIBS;PRIVATE_LINK_LIBS" ${ARGN})
  set(target chromatag_${ARG_NAME})
  add_library(${target} STATIC ${ARG_SRCS})
  add_library(ChromaTag::${ARG_NAME} ALIAS ${target})
  target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_LINK_LIBS} PRIVATE ${ARG_PRIVATE_LINK_LIBS})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  chromatag_target_defaults(${target})
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
