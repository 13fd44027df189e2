# Build time on a 2-core machine (docs/tests_and_ci.md, "Where CI's time goes").
#
# Unity builds: CMake compiles a target's .cc files in batches, each batch one translation unit
# that includes them in turn, so the heavy headers every file shares (the twin's headers, Eigen's
# templates beyond the precompiled core, CLI11, nlohmann/json, Catch2) are parsed and instantiated
# once per batch instead of once per file. Files of one target must therefore not define the same
# name at namespace scope in their own files (anonymous namespaces included): a file-local helper
# that two files need lives in a header, a test's fixtures in a namespace named after its file.
# PREPREG_UNITY_BUILD=OFF compiles file by file, the quicker loop when editing one file.
option(PREPREG_UNITY_BUILD "Compile each target's sources in batches (CMake unity build)" ON)
set(PREPREG_UNITY_BATCH_SIZE 8 CACHE STRING
    "Sources per unity batch: larger saves more parsing, smaller keeps both cores busy and rebuilds less")
if(PREPREG_UNITY_BUILD)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE ${PREPREG_UNITY_BATCH_SIZE})
endif()

# LLVM's linker when installed (scripts/packages.sh): the test executables link about 2.5x
# faster than with GNU ld, and every test target is linked once per tree.
option(PREPREG_LLD "Link with lld when the compiler accepts -fuse-ld=lld" ON)
if(PREPREG_LLD)
  include(CheckLinkerFlag)
  check_linker_flag(CXX -fuse-ld=lld prepreg_have_lld)
  if(prepreg_have_lld)
    add_link_options(-fuse-ld=lld)
  endif()
endif()
