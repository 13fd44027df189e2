# Precompiled headers shared by every C++ target (issue 2: CI time).
#
# Most files parse the same standard headers, Eigen and fmt (Eigen's Core and SparseCore alone
# take about 1.5 s per file); a precompiled header saves that parse. Measured on the twin
# library (60 files, -j2): 173 s -> 125 s of compiler time. nlohmann/json was tried in it too
# and made it slower (155 s): a larger header costs every file that loads it, and only a few
# files use json. PCL, CLI11 and spdlog stay out (few files, or defines of their own).
#
# GCC accepts a precompiled header only when compiled with the same options, so there are three
# holders: the libraries and tools (the build type's flags), the position-independent libraries
# (-fPIC: the ones the V4L2 shim links, sim_hw/CMakeLists.txt; everything else is PIE, Debian's
# default) and the tests (which add -O1, tests/CMakeLists.txt). Each holder is a one-file static
# library whose header the other targets reuse (REUSE_FROM), so the header is compiled a few
# times per build, not once per target.
# A target whose options differ anyway (GCC then ignores the file) still compiles correctly:
# the header is force-included as text. So every reusing target gets the holder's usage
# requirements (Eigen's include directory, fmt's FMT_SHARED, -fopenmp): without them GCC
# rejected the header in about 60 of 320 files (most of the drivers, some tests), which then parsed
# it as text.
# A target with the property PREPREG_NO_PCH keeps its own headers only.

set(PREPREG_PCH_HEADERS
  <algorithm> <array> <cmath> <cstdint> <functional> <limits> <memory> <optional> <stdexcept>
  <string> <string_view> <utility> <vector>
  <Eigen/Core> <Eigen/SparseCore> <fmt/format.h>)

option(PREPREG_PRECOMPILED_HEADERS "Precompile the headers most files share" ON)
# Clang refuses a precompiled header made with other options where GCC falls back to the text.
# The options that differ between targets are -pthread (LCM's flags bring it to the bus targets:
# "POSIX thread support was disabled in PCH file"), -fPIC (the _pic holder) and the OpenNI2
# plug-in's hidden visibility. So under clang every holder and every target reusing it compiles
# with -pthread, and a target with a visibility preset keeps its own headers. Per file clang then
# compiles about as fast as GCC with its header; without one it parses Eigen in every file again.
# PREPREG_CLANG_PRECOMPILED_HEADERS=OFF turns the header off under clang only.
option(PREPREG_CLANG_PRECOMPILED_HEADERS "Use the precompiled headers under clang too" ON)
if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang" AND NOT PREPREG_CLANG_PRECOMPILED_HEADERS)
  set(PREPREG_PRECOMPILED_HEADERS OFF)
endif()
set(PREPREG_PCH_CLANG_OPTIONS "")
if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  set(PREPREG_PCH_CLANG_OPTIONS -pthread)
endif()

# Makes a holder target `name` in the calling directory (so it gets that directory's options),
# and `name`_pic, its position-independent twin. Further arguments are headers of that folder's
# own that most of its files include (the tests: Catch2).
function(prepreg_pch_holder name)
  if(NOT PREPREG_PRECOMPILED_HEADERS)
    return()
  endif()
  foreach(holder ${name} ${name}_pic)
    add_library(${holder} STATIC ${PROJECT_SOURCE_DIR}/scripts/cmake/pch_holder.cc)
    target_link_libraries(${holder} PRIVATE Eigen3::Eigen fmt::fmt OpenMP::OpenMP_CXX)
    target_compile_options(${holder} PRIVATE ${PREPREG_PCH_CLANG_OPTIONS})
    target_precompile_headers(${holder} PRIVATE ${PREPREG_PCH_HEADERS} ${ARGN})
  endforeach()
  set_property(TARGET ${name}_pic PROPERTY POSITION_INDEPENDENT_CODE ON)
endfunction()

# Every C++ library and executable made in `directory` (and below) reuses the header of
# `holder` (position-independent targets: of `holder`_pic).
function(prepreg_reuse_pch directory holder)
  if(NOT PREPREG_PRECOMPILED_HEADERS)
    return()
  endif()
  get_property(targets DIRECTORY ${directory} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    if(t MATCHES "^${holder}(_pic)?$" OR NOT type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|MODULE_LIBRARY|EXECUTABLE)$")
      continue()
    endif()
    get_target_property(pic ${t} POSITION_INDEPENDENT_CODE)
    set(from ${holder})
    if(pic OR type MATCHES "^(SHARED|MODULE)_LIBRARY$")
      set(from ${holder}_pic)
    endif()
    get_target_property(sources ${t} SOURCES)
    get_target_property(opted_out ${t} PREPREG_NO_PCH)
    if(NOT sources MATCHES "\\.cc" OR opted_out)
      continue()  # C sources or generated code only, or opted out
    endif()
    # Clang also refuses a header made with another default visibility (the OpenNI2 plug-in
    # hides its symbols, sim_hw/CMakeLists.txt); GCC uses the header anyway.
    get_target_property(visibility ${t} CXX_VISIBILITY_PRESET)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang" AND visibility)
      continue()
    endif()
    target_precompile_headers(${t} REUSE_FROM ${from})
    target_link_libraries(${t} PRIVATE Eigen3::Eigen fmt::fmt OpenMP::OpenMP_CXX)
    target_compile_options(${t} PRIVATE ${PREPREG_PCH_CLANG_OPTIONS})
  endforeach()
  get_property(subdirectories DIRECTORY ${directory} PROPERTY SUBDIRECTORIES)
  foreach(d IN LISTS subdirectories)
    prepreg_reuse_pch(${d} ${holder})
  endforeach()
endfunction()
