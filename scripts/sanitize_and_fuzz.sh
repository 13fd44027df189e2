#!/usr/bin/env bash
# The sanitizer and fuzzing run: one clang build with ASan + UBSan and libFuzzer's edge coverage
# (build-asan/, docs/fuzzing.md), its tests, then every fuzz harness for a while: CI's second
# step (.ci/run). Installs clang with apt if it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

# 1. One clang build with ASan + UBSan and libFuzzer's edge coverage (docs/fuzzing.md): the
#    sanitizer tests and the fuzz harnesses share its libraries, so they compile once.
#    -O1 -g1 (line tables and function names, no variable info) is what the sanitizer reports
#    need and compiles in well under half the time of -O2 -g with the sanitizers.
#    UBSan's per-access checks (alignment, null, pointer-overflow, object-size) are left out
#    (PREPREG_SANITIZE_ACCESS_CHECKS=OFF): they made this build about 30 % longer to compile and
#    its tests about 3x slower to run, and ASan reports the null and out-of-bounds accesses
#    they would (docs/tests_and_ci.md).
#    Tested here: the twin (with its optional effects), the independent sheet (sim_hw/real_sheet),
#    the reference sheet (sim_hw/spline_shell), the drivers (config, frame monitor, V4L2 back-end
#    over its in-process emulation, session recording, LCM bus, iiwa kinematics), the simulated
#    D415, the fake world (arms, grippers, true sheet, a memq run with emulated cameras), the
#    marker pipeline and the sheet tracker
#    (also on simulated D415s), the cell controller (label cell: start-up, configs, pacing,
#    workers, calibration monitor, settled states from a log), the terminal monitor and log tools,
#    grasp planning, and `twin batch` (manifests, several small diagnoses, resuming).
#    Not here: the LD_PRELOAD shim and OpenNI2 tests (the sanitizer runtime would have to be
#    preloaded before the shim, and OpenNI2 and PCL are uninstrumented system libraries); the
#    cell cases that must keep the cell's 10 Hz against its watchdog limits (cell_real_time,
#    tests/CMakeLists.txt), which this build runs some 25 times slower; the long identification,
#    diagnosis and learning cases (one identification end to end runs below).
source scripts/phase.sh
source scripts/packages.sh
phase "install clang" bash scripts/install_packages.sh "${SANITIZER_PACKAGES[@]}"
generator=()
[[ -f build-asan/CMakeCache.txt ]] || ! command -v ninja > /dev/null || generator=(-G Ninja)
# Without MPI (-DPREPREG_WITH_MPI=OFF): this tree is the build a machine without OpenMPI gets, so
# its batch and grasp-planning tests check that one; the MPI runs are the Release suite's label mpi.
CC=clang CXX=clang++ phase "configure sanitizer" cmake -S . -B build-asan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPREPREG_SANITIZE=ON \
  -DPREPREG_WITH_MPI=OFF -DPREPREG_SANITIZE_ACCESS_CHECKS=OFF -DPREPREG_FUZZ=ON -DPREPREG_FUZZ_COVERAGE=edges \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
phase "build sanitizer" cmake --build build-asan -j2 --target twin_tests effects_tests sim_hw_tests drivers_tests lcm_bus_tests \
  iiwa_kinematics_tests camera_sim_tests world_tests real_sheet_tests spline_shell_tests tracking_tests tracker_tests \
  camera_tracking_tests monitor_tests cell_log_diagnosis_tests grasp_planning_tests cell_tests batch_tests fuzz_harnesses
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"  # two test processes on two cores (scripts/test.sh)
# Each ctest call selects by label or name: --no-tests=error fails one that selects nothing, and
# its junit file shows that every selected entry ran and passed (no skips): check_tests_ran.sh.
results="$PWD/build-asan/test-results"
rm -rf "$results" && mkdir -p "$results"
phase "test sanitizer" ctest --test-dir build-asan --output-on-failure -j2 --no-tests=error --output-junit "$results/sanitizer.xml" \
  -L "^(twin|effects|drivers|lcm_bus|iiwa|camera_sim|world|real_sheet|spline_shell|tracking|tracker|camera_tracking|monitor|cell_log|grasp_planning|cell|batch)$"
# Identification end to end (lab trial, evaluator, adjoint and tangents) once under the
# sanitizers; the other identification cases repeat the same code paths for longer.
phase "test sanitizer identification" ctest --test-dir build-asan -R "adjoint gradient of the marker misfit" --output-on-failure \
  --no-tests=error --output-junit "$results/identification.xml"

# 2. Smoke fuzzing: each harness replays its committed corpus (regression inputs included), then
#    fuzzes for a few seconds (scripts/run_fuzzer.sh; PREPREG_FUZZ_SMOKE_SECONDS).
phase "fuzz smoke" ctest --test-dir build-asan -L fuzz_smoke --output-on-failure -j2 --no-tests=error \
  --output-junit "$results/fuzz_smoke.xml"
bash scripts/check_tests_ran.sh --selected build-asan "$results"/*.xml
