// cell_world: the cell's fake hardware in one process (see sim_hw/cell_world.h and
// docs/fake_world.md):
//   cell_world --config CELL.json --world WORLD.json [--lcm URL] [--max-seconds S]
//              [--emulation-env FILE] [--max-real-time-factor F] [--lockstep CLIENT]... [--quiet]
// Loads the ply as the cell config's grasp plan says, then serves the arms, grippers and cameras
// on its simulation clock (SIM_CLOCK; sim_hw/world_clock.h) until --max-seconds of wall time pass
// (0 = until SIGINT/SIGTERM). The clock runs as fast as the physics allows, at most
// --max-real-time-factor (default 1: real time; 0: no limit), and never past the hold of a
// --lockstep client (the cell controller on "clock": "sim"), which it waits for from time 0. --emulation-env writes the two lines a
// launcher passes to the cell process (`env $(cat FILE) build/cell/cell_controller ...`):
//   PREPREG_V4L2_EMULATION=/dev/video0=<node>,...   LD_PRELOAD=<path of libprepreg_v4l2_shim.so>
//   PREPREG_V4L2_EMULATION_CLOCK=sim   (the devices' buffers are stamped on the world's clock)
// One status line per second unless --quiet. Exit status: 0 stopped on request or at
// --max-seconds; 1 bad config or a start-up failure (the message says which file and field, or
// which gripper's hold position is unreachable).

#include <cstdio>
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <atomic>
#include <cstdlib>
#include <csignal>
#include <filesystem>
#include <unistd.h>

#include "common/durable_file.h"
#include "sim_hw/cell_world.h"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

// The shim is built next to this executable (build/sim_hw/).
std::string shim_path() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return (exe.parent_path() / "libprepreg_v4l2_shim.so").string();
}

// Written durably (common/durable_file.h): a launcher waiting for the file never sees half of it.
// PREPREG_V4L2_EMULATION_CLOCK tells the cell that these devices stamp their buffers on the
// world's simulation clock, so that a cell on the wall can refuse them with a reason.
void write_emulation_env(const std::string& path, const std::string& spec) {
  prepreg::write_file_atomically(path, "PREPREG_V4L2_EMULATION=" + spec + "\n" + "LD_PRELOAD=" + shim_path() + "\n" +
                                           "PREPREG_V4L2_EMULATION_CLOCK=sim\n");
}

std::string status_line(const sim_hw::WorldSnapshot& s, int arms) {
  std::string cams;
  for (const auto& [name, frames] : s.camera_frames) cams += fmt::format(" {}={}", name, frames);
  std::string holding;
  for (const auto& g : s.holding) {
    if (!holding.empty()) holding += ',';
    holding += g;
  }
  return fmt::format(
      "t={:.1f}s rtf={:.2f}{} step={:.1f}ms (max {:.1f}, failed {}) frames:{} arms={} moving={} "
      "holding=[{}] sag={:.3f}m truth={} cmds={}/{} rejected={}",
      s.sim_time_s, s.real_time_factor, s.held_by.empty() ? "" : " held by " + s.held_by, s.physics.last_step_ms,
      s.physics.max_step_ms, s.physics.failures, cams, arms, s.arms_moving, holding, s.sag_m,
      s.counters.truth_published, s.counters.arm_commands, s.counters.gripper_commands,
      s.counters.arm_commands_rejected + s.counters.gripper_commands_rejected);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // status lines reach a log file as they happen
  // OpenMP threads that wait by spinning steal the cores the cameras, the physics and the cell
  // process need; libgomp reads the policy when it loads, so set it and start again once.
  if (!std::getenv("OMP_WAIT_POLICY")) {
    ::setenv("OMP_WAIT_POLICY", "passive", 1);
    ::execv("/proc/self/exe", argv);  // returns only on failure: then run on as we are
  }
  CLI::App app{"The cell's fake hardware: true sheet, simulated iiwa arms, grippers and D415s on LCM"};
  std::string cell_path, world_path, lcm_url = drivers::kLoopbackLcmUrl, env_path;
  double max_seconds = 0;
  bool quiet = false;
  sim_hw::WorldClockOptions clock;
  app.add_option("--config", cell_path, "cell config JSON (arms, grippers, cameras, job.plan_file)")->required();
  app.add_option("--world", world_path, "world config JSON (true sheet, material, camera poses)")->required();
  app.add_option("--lcm", lcm_url, "LCM URL (default loopback udpm, ttl=0)");
  app.add_option("--max-seconds", max_seconds, "stop after this long (s); 0 = until killed")->check(CLI::NonNegativeNumber);
  app.add_option("--emulation-env", env_path, "write PREPREG_V4L2_EMULATION and LD_PRELOAD lines here");
  app.add_option("--max-real-time-factor", clock.max_real_time_factor,
                 "simulated seconds per wall second at most (default 1; 0: as fast as the physics allows)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--lockstep", clock.lockstep,
                 "a client (e.g. cell_controller) whose SIM_CLOCK_HOLD the clock waits for, from time 0");
  app.add_option("--lockstep-silence-s", clock.client_silence_s,
                 "wall seconds a lockstep client may stay silent while the clock waits on it before it is dropped")
      ->check(CLI::PositiveNumber);
  app.add_flag("--quiet", quiet, "no status lines");
  CLI11_PARSE(app, argc, argv);

  sim_hw::WorldConfig config;
  try {
    config = sim_hw::read_world_config(cell_path, world_path);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cell_world: {}\n", e.what());
    return 1;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    drivers::LcmBus bus(lcm_url);
    sim_hw::CellWorld world(config, bus, clock);
    const auto& load = world.load_report();
    if (!quiet)
      fmt::print("cell_world: ply loaded ({}; {} Newton iterations, {:.1f} s), sag {:.3f} m\n",
                 config.sheet.description, load.iterations, load.seconds, world.sheet().sag_m());
    if (!env_path.empty()) write_emulation_env(env_path, world.emulation_spec());
    if (!quiet) fmt::print("emulation {}\n", world.emulation_spec());
    std::fflush(stdout);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(max_seconds);
    while (!g_stop && (max_seconds == 0 || std::chrono::steady_clock::now() < end)) {
      world.run_for(std::chrono::seconds(1), &g_stop);
      if (!quiet) fmt::print("{}\n", status_line(world.snapshot(), static_cast<int>(world.arms().size())));
      if (const std::string notice = world.clock().take_notice(); !notice.empty()) fmt::print("cell_world: {}\n", notice);
      std::fflush(stdout);
    }
    if (!quiet) fmt::print("cell_world: stopped\n");
  } catch (const std::exception& e) {
    fmt::print(stderr, "cell_world: {}\n", e.what());
    return 1;
  }
  return 0;
}
