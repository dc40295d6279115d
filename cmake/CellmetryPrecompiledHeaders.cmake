# Precompiled headers: Eigen and Ceres (and GoogleTest for the suites) are parsed once per family
# of targets instead of once per file. Nearly every file includes them, and parsing them was most
# of a file's compile time (a test suite's file ~8 s, of which the headers ~5 s), which CI's
# 30 minutes on two cores need back.
#
# A precompiled header is only used by files compiled with the same flags as the one that built
# it, so targets share one per family (REUSE_FROM):
#   cellmetry_basics        the core layers, the experiments and the plugins (shared objects, -fPIC)
#   cellmetry_test_support  the test suites (executables)
# The app builds its own. A header that does not match is not an error for GCC: the file is
# compiled from the text instead (slower, same result), and -Winvalid-pch says so in the build log.
# Clang refuses a mismatched one outright, so in the clang build (scripts/sanitize.sh, the
# fuzzers) a target of four files or more builds its own and a smaller one none (building the
# header would cost what it saves).
#
# -DCELLMETRY_PRECOMPILE_HEADERS=OFF compiles every file from its own includes (a check that each
# file includes what it uses).
option(CELLMETRY_PRECOMPILE_HEADERS "Precompile Eigen, Ceres and GoogleTest headers" ON)

set(CELLMETRY_PCH_HEADERS
  <algorithm> <array> <cmath> <functional> <map> <memory> <optional> <string> <vector>
  <Eigen/Core> <Eigen/Geometry> <ceres/ceres.h>)

# cellmetry_precompile_headers(TARGET [FROM HOLDER] [EXTRA header...]): TARGET uses HOLDER's
# precompiled header (GCC), or builds its own of the common headers and EXTRA (HOLDER itself).
function(cellmetry_precompile_headers target)
  cmake_parse_arguments(ARG "" "FROM" "EXTRA" ${ARGN})
  if(NOT CELLMETRY_PRECOMPILE_HEADERS)
    return()
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # CMake defines <target>_EXPORTS in each shared library's files; nothing here reads it, and a
    # macro that differs between targets makes a shared header unusable.
    set_target_properties(${target} PROPERTIES DEFINE_SYMBOL "")
    if(ARG_FROM)
      target_precompile_headers(${target} REUSE_FROM ${ARG_FROM})
    else()
      target_precompile_headers(${target} PRIVATE ${CELLMETRY_PCH_HEADERS} ${ARG_EXTRA})
    endif()
    return()
  endif()
  get_target_property(sources ${target} SOURCES)
  list(LENGTH sources source_count)
  if(source_count GREATER_EQUAL 4)
    target_precompile_headers(${target} PRIVATE ${CELLMETRY_PCH_HEADERS} ${ARG_EXTRA})
  endif()
endfunction()
