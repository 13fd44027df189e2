# The Debian packages the project uses, sourced by scripts/setup.sh (PROJECT_PACKAGES),
# scripts/sanitize_and_fuzz.sh (SANITIZER_PACKAGES) and .ci/run (both, in one apt call).
# Installed without recommends by scripts/install_packages.sh.
PROJECT_PACKAGES=(
  build-essential cmake pkg-config             # compiler and build
  ninja-build                                  # the build tool setup.sh configures (a target's files compile before the libraries it links are done)
  ccache                                       # compiler cache: later builds of the same sources (scripts/cmake/compiler_cache.cmake)
  lld                                          # LLVM's linker: the test executables link faster (scripts/cmake/build_speed.cmake)
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
  calculix-ccx                                 # CalculiX, the reference's third opinion (optional: its tests built only when found)
)
SANITIZER_PACKAGES=(
  clang libclang-rt-14-dev libomp-14-dev       # the ASan + UBSan + libFuzzer build (docs/fuzzing.md)
)
