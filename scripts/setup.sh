#!/usr/bin/env bash
# One idempotent set-up step for a fresh Debian 12 machine: install exactly the Debian packages
# the project uses (no recommends), then configure and build (Release, -j2) into build/.
# Re-running it only rebuilds what changed. Set PREPREG_SKIP_APT=1 to skip the install step
# (for machines where the packages are already present and apt is not usable).
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake pkg-config             # compiler and build
  ccache                                       # compiler cache: later builds of the same sources (scripts/cmake/compiler_cache.cmake)
  libeigen3-dev                                # Eigen (twin)
  libsuitesparse-dev libopenblas-dev           # CHOLMOD, with OpenBLAS as its BLAS
  libnlopt-cxx-dev                             # NLopt C++ (identification)
  libopenni2-dev libv4l-dev                    # camera drivers
  libpcl-dev                                   # tracking
  liblcm-dev liblcm-bin libglib2.0-dev         # LCM bus and lcm-gen (lcm.pc needs glib)
  catch2                                       # tests
  nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  default-jdk-headless liblcm-java libjchart2d-java  # lcm-spy with our types (optional jar)
  xvfb                                         # lcm-spy on a headless machine (scripts/lcm_spy.sh)
  iproute2                                     # network namespaces of the udpm and fake-cell tests (scripts/with_loopback_lcm.sh)
  libopenmpi-dev openmpi-bin                   # twin batch across MPI ranks (optional: built only when found)
)

source scripts/phase.sh
phase "install packages" bash scripts/install_packages.sh "${PACKAGES[@]}"
phase "configure Release" cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
phase "build Release" cmake --build build -j2
