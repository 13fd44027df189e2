#pragma once
// The cell benchmark's inputs: a recorded camera session of the fake cell (the true hanging
// sheet of the fake world rendered by simulated D415s on the simulated clock, so recording does
// not depend on how busy the machine is) and the fake cell's config turned into the benchmark's
// (replay cameras at the recorded pace, in-process LCM, the cycle rate and twin size asked for).
#include <filesystem>
#include <string>

#include "cell/cell_config.h"
#include "sim_hw/true_sheet.h"
#include "sim_hw/world_config.h"

namespace cell_bench {

inline constexpr int kCameraFps = 30;  // the D415 mode of the benchmark (848x480 @ 30 fps)

// The fake world's config (cell config + world config) with every camera at kCameraFps.
sim_hw::WorldConfig bench_world_config(const std::string& cell_config_path, const std::string& world_path);

// Whether `dir` already holds a recorded session (session.json).
bool has_session(const std::filesystem::path& dir);

// Records `seconds` of every world camera (848x480 @ kCameraFps) looking at `sheet` as it hangs
// into the session directory `dir` (must not hold a session yet; it is recorded into
// "<dir>.partial" and renamed to `dir` once complete). Throws std::runtime_error
// naming the camera when a camera fails or records too few frames.
void record_session(const sim_hw::WorldConfig& world, const sim_hw::TrueSheet& sheet,
                    const std::filesystem::path& dir, double seconds);

// Writes `work_dir`/bench_cell.json: the cell config at `cell_config_path` with cell.lcm_url
// memq://, cell.cycle_hz = hz, twin.sheet.target_triangles = triangles (0: the config's own),
// the wall clock, no experiment, and each
// camera replaced by "<session>#<name>?pace=recorded&loop=1&rebase=1&live=1" at kCameraFps (its
// calibration kept: the cell uses its own camera poses, not the world's true ones). Returns it
// read back (read_cell_config: errors name the file and field).
cell::CellConfig bench_cell_config(const std::string& cell_config_path, const std::filesystem::path& session,
                                   double hz, int triangles, const std::filesystem::path& work_dir);

}  // namespace cell_bench
