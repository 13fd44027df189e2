# Compiles through ccache when the machine has it (scripts/setup.sh installs it), so a second
# build of the same sources in the same folder - the trees again after a branch switch or a clean,
# CI rerun where the machine keeps its cache and clones to the same path - takes its objects from
# the cache instead of compiling them again.
# A clone in another folder shares entries only with PREPREG_UNITY_BUILD=OFF: CMake 3.25 writes
# each unity batch as includes of its files' absolute paths, which ccache hashes with the batch
# (CMake 3.32's UNITY_BUILD_RELOCATABLE writes them relative; Debian 12 has 3.25).
#
# The settings travel on the launcher's command line, not in the user's ccache.conf:
# - base_dir = the source tree: absolute paths under it on the command line are hashed
#   relative to the build directory (two clones in different folders share the entries of
#   files compiled one by one);
# - hash_dir = false: -g1 (the sanitizer tree) would otherwise hash the build directory;
# - sloppiness pch_defines,time_macros + include_file_mtime/ctime: what ccache needs to cache
#   compilations that use the precompiled header (scripts/cmake/precompiled_headers.cmake), whose
#   .gch is rebuilt with a new time stamp in each tree;
# - depend mode: a miss hashes the compiler's own -MD output instead of running the preprocessor
#   a second time, so a cold cache (a fresh CI machine) costs 1-3 % over a plain build, not
#   5-20 % (ccache's performance notes).
# PREPREG_CCACHE=OFF compiles directly.
option(PREPREG_CCACHE "Compile through ccache when it is installed" ON)
find_program(PREPREG_CCACHE_PROGRAM ccache)
if(PREPREG_CCACHE AND PREPREG_CCACHE_PROGRAM AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(prepreg_ccache_launcher
      ${CMAKE_COMMAND} -E env
      CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
      CCACHE_NOHASHDIR=1
      CCACHE_DEPEND=1
      CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
      ${PREPREG_CCACHE_PROGRAM})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${prepreg_ccache_launcher})
  set(CMAKE_C_COMPILER_LAUNCHER ${prepreg_ccache_launcher})
  message(STATUS "Compiling through ${PREPREG_CCACHE_PROGRAM} (PREPREG_CCACHE=OFF to compile directly)")
endif()
