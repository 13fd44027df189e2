# Finds every package on the design card, once, and fails at configure time with the name of the
# Debian 12 package that provides whatever is missing (scripts/setup.sh installs all of them).
#
# Imported targets made here (used by the per-folder CMakeLists):
#   Eigen3::Eigen, prepreg::cholmod, NLopt::nlopt_cxx, prepreg::openni2, prepreg::v4l2,
#   prepreg::pcl, prepreg::lcm, Catch2::Catch2WithMain, nlohmann_json::nlohmann_json, CLI11::CLI11,
#   spdlog::spdlog, fmt::fmt, OpenMP::OpenMP_CXX

function(prepreg_missing what debian_package)
  message(FATAL_ERROR
    "${what} not found. On Debian 12 install it with:\n"
    "  sudo apt-get install --no-install-recommends ${debian_package}\n"
    "(scripts/setup.sh installs every package this project uses.)")
endfunction()

find_package(PkgConfig QUIET)
if(NOT PkgConfig_FOUND)
  prepreg_missing("pkg-config" "pkg-config")
endif()

find_package(Eigen3 3.4 QUIET NO_MODULE)
if(NOT TARGET Eigen3::Eigen)
  prepreg_missing("Eigen3 >= 3.4" "libeigen3-dev")
endif()

# The twin's background factorisation and the cell's workers are std::threads.
find_package(Threads REQUIRED)

find_package(OpenMP QUIET COMPONENTS CXX)
if(NOT OpenMP_CXX_FOUND)
  prepreg_missing("OpenMP for C++ (libgomp)" "g++")
endif()

# SuiteSparse 5.12 (Debian 12) ships no CMake config for CHOLMOD: find header and libraries.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
find_library(AMD_LIBRARY amd)
find_library(COLAMD_LIBRARY colamd)
if(NOT CHOLMOD_INCLUDE_DIR OR NOT CHOLMOD_LIBRARY OR NOT SUITESPARSECONFIG_LIBRARY)
  prepreg_missing("CHOLMOD (SuiteSparse)" "libsuitesparse-dev")
endif()
add_library(prepreg::cholmod INTERFACE IMPORTED)
target_include_directories(prepreg::cholmod INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(prepreg::cholmod INTERFACE
  ${CHOLMOD_LIBRARY} ${AMD_LIBRARY} ${COLAMD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})
# CHOLMOD's supernodal factorization runs on BLAS; OpenBLAS makes it several times faster than
# the reference BLAS. It is a run-time choice (libblas.so.3 alternative), so only warn.
if(NOT EXISTS /usr/lib/x86_64-linux-gnu/openblas-pthread/libblas.so.3
   AND NOT EXISTS /usr/lib/aarch64-linux-gnu/openblas-pthread/libblas.so.3)
  message(WARNING "OpenBLAS not found: CHOLMOD will use the reference BLAS and be several times "
                  "slower. Install libopenblas-dev.")
endif()

# NLopt installs two configs under the same package name; the C++ API (target
# NLopt::nlopt_cxx) is the one under cmake/nlopt_cxx, so look only there.
find_package(NLopt QUIET CONFIG
             PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/nlopt_cxx NO_DEFAULT_PATH)
if(NOT TARGET NLopt::nlopt_cxx)
  prepreg_missing("NLopt (C++ API)" "libnlopt-cxx-dev")
endif()

# OpenNI2: no pkg-config or CMake config in Debian.
find_path(OPENNI2_INCLUDE_DIR OpenNI.h PATH_SUFFIXES openni2)
find_library(OPENNI2_LIBRARY OpenNI2)
if(NOT OPENNI2_INCLUDE_DIR OR NOT OPENNI2_LIBRARY)
  prepreg_missing("OpenNI2" "libopenni2-dev")
endif()
add_library(prepreg::openni2 INTERFACE IMPORTED)
target_include_directories(prepreg::openni2 INTERFACE ${OPENNI2_INCLUDE_DIR})
target_link_libraries(prepreg::openni2 INTERFACE ${OPENNI2_LIBRARY})

pkg_check_modules(LIBV4L2 QUIET IMPORTED_TARGET libv4l2)
find_path(V4L2_VIDEODEV_INCLUDE_DIR linux/videodev2.h)
if(NOT LIBV4L2_FOUND OR NOT V4L2_VIDEODEV_INCLUDE_DIR)
  prepreg_missing("libv4l2 and linux/videodev2.h" "libv4l-dev linux-libc-dev")
endif()
add_library(prepreg::v4l2 INTERFACE IMPORTED)
target_link_libraries(prepreg::v4l2 INTERFACE PkgConfig::LIBV4L2)

# lcm.pc requires glib-2.0.pc, so a missing libglib2.0-dev looks like a missing LCM.
pkg_check_modules(GLIB2 QUIET glib-2.0)
if(NOT GLIB2_FOUND)
  prepreg_missing("glib-2.0 (needed by lcm.pc)" "libglib2.0-dev")
endif()
pkg_check_modules(LCM QUIET IMPORTED_TARGET lcm)
if(NOT LCM_FOUND)
  prepreg_missing("LCM" "liblcm-dev")
endif()
find_program(LCM_GEN_EXECUTABLE lcm-gen)
if(NOT LCM_GEN_EXECUTABLE)
  prepreg_missing("lcm-gen" "liblcm-bin")
endif()
add_library(prepreg::lcm INTERFACE IMPORTED)
target_link_libraries(prepreg::lcm INTERFACE PkgConfig::LCM)

# PCL's config probes VTK, which needs the C language; the cell never renders, so skip VTK.
set(CMAKE_DISABLE_FIND_PACKAGE_VTK ON)
find_package(PCL 1.12 QUIET COMPONENTS common kdtree search filters features segmentation surface)
if(NOT PCL_FOUND)
  prepreg_missing("PCL >= 1.12" "libpcl-dev")
endif()
add_library(prepreg::pcl INTERFACE IMPORTED)
target_include_directories(prepreg::pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(prepreg::pcl INTERFACE ${PCL_LIBRARIES})
target_compile_definitions(prepreg::pcl INTERFACE ${PCL_DEFINITIONS})

find_package(nlohmann_json 3.10 QUIET CONFIG)
if(NOT TARGET nlohmann_json::nlohmann_json)
  prepreg_missing("nlohmann-json" "nlohmann-json3-dev")
endif()
find_package(CLI11 QUIET CONFIG)
if(NOT TARGET CLI11::CLI11)
  prepreg_missing("CLI11" "libcli11-dev")
endif()
find_package(fmt QUIET CONFIG)
if(NOT TARGET fmt::fmt)
  prepreg_missing("fmt" "libfmt-dev")
endif()
find_package(spdlog QUIET CONFIG)
if(NOT TARGET spdlog::spdlog)
  prepreg_missing("spdlog" "libspdlog-dev")
endif()

if(PREPREG_BUILD_TESTS)
  find_package(Catch2 2.13 QUIET CONFIG)
  if(NOT TARGET Catch2::Catch2WithMain)
    prepreg_missing("Catch2 2.13" "catch2")
  endif()
endif()
