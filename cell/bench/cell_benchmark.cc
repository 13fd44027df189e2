// cell_benchmark: the issue-5 cell benchmark (prints figures; not a test). The real
// CellController runs at --hz on a recorded session of the fake cell's three D415s (848x480 @ 30
// fps, replayed at the recorded pace, so the cameras cost the measured cores only what reading
// frames from disk costs), with the fake world's simulated arms and grippers answering on the
// same in-process LCM bus. Phases: "still" (the ply held still, the usual case) and "moving"
// (one gripper's goal moved back and forth, so the twin steps a moving clamp under load).
//
//   cell_benchmark [--seconds S] [--triangles N] [--hz 30] [--memory-every-s 10]
//                  [--session DIR] [--phase both|still|moving] [--threads 1] [--lockstep]
//                  [--twin-priority idle|normal]
//
// Prints per phase a line "figure: cell 848x480x3 twin N tris (PHASE): rate .. Hz latency median
// .. ms p99 .. ms tracker .. twin step .. cycle ..", "memory: t=.. s rss=.. MB" every
// --memory-every-s and a final "memory growth" line, with the load average.
// Exit codes: 0 figures printed; 1 config or recording error; 2 start-up FAILED; 3 no cycles.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <omp.h>
#include <unistd.h>

#include <filesystem>

#include "cell/bench/bench_robots.h"
#include "cell/bench/bench_session.h"
#include "cell/bench/cycle_figures.h"
#include "cell/cell_controller.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Where the moving phase moves a gripper: the first grasp held by an arm (the operator's
// MANUAL grasp cannot be moved by the cell), back and forth along x.
int moving_grasp(const cell::CellController& cell) {
  const auto& grasps = cell.plan().grasps;
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    const auto* g = cell.config().hardware.find_gripper(grasps[i].gripper);
    if (g && !g->arm.empty()) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cell benchmark: cycle rate, latency, stage times and memory of the cell controller"};
  double seconds = 60, hz = 30, memory_every_s = 10, record_s = 2, warmup_s = 2, sweep_m = 0.05;
  int triangles = 0, threads = 1;  // 0: the cell config's twin
  std::string session, phase = "both";
  std::string cell_path = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/fake_cell.json";
  std::string world_path = std::string(PREPREG_SOURCE_DIR) + "/sim_hw/examples/fake_world.json";
  app.add_option("--seconds", seconds, "measured seconds per phase")->check(CLI::PositiveNumber);
  app.add_option("--triangles", triangles, "twin target_triangles (default: the fake cell config's)")
      ->check(CLI::PositiveNumber);
  app.add_option("--hz", hz, "cell.cycle_hz")->check(CLI::PositiveNumber);
  app.add_option("--memory-every-s", memory_every_s, "RSS sample period (s)")->check(CLI::PositiveNumber);
  app.add_option("--session", session, "camera session DIR: reused if it holds one, else recorded into it and kept");
  app.add_option("--record-seconds", record_s, "seconds of camera frames to record (looped in replay)")
      ->check(CLI::PositiveNumber);
  app.add_option("--warmup-s", warmup_s, "seconds at the start of each phase left out of the figures");
  app.add_option("--phase", phase, "both, still or moving")->check(CLI::IsMember({"both", "still", "moving"}));
  app.add_option("--sweep-m", sweep_m, "moving phase: how far the gripper goal moves along x (m)");
  app.add_option("--threads", threads, "OpenMP threads of the tracker and twin (cell_controller's default 1)")
      ->check(CLI::PositiveNumber);
  bool lockstep = false;
  app.add_flag("--lockstep", lockstep, "cell.twin_lockstep: every cycle waits for the twin's step");
  std::string twin_factorisation = "background";
  app.add_option("--twin-factorisation", twin_factorisation,
                 "cell.twin_background_factorization: background (true) or own-thread (false)")
      ->check(CLI::IsMember({"background", "own-thread"}));
  std::string twin_priority = "normal";
  app.add_option("--twin-priority", twin_priority,
                 "cell.twin_priority of the twin's worker thread (idle: for a machine that runs the cell alone)")
      ->check(CLI::IsMember({"idle", "normal"}));
  app.add_option("--config", cell_path, "cell config (default: the fake cell)");
  app.add_option("--world", world_path, "world config (default: the fake world)");
  CLI11_PARSE(app, argc, argv);
  omp_set_num_threads(threads);

  const std::filesystem::path work =
      std::filesystem::temp_directory_path() / fmt::format("cell_benchmark_{}", ::getpid());
  const std::filesystem::path session_dir = session.empty() ? work / "session" : std::filesystem::path(session);
  std::unique_ptr<drivers::LcmBus> bus;
  std::unique_ptr<cell_bench::BenchRobots> robots;
  cell::CellConfig config;
  try {
    const sim_hw::WorldConfig world = cell_bench::bench_world_config(cell_path, world_path);
    bus = std::make_unique<drivers::LcmBus>("memq://");
    robots = std::make_unique<cell_bench::BenchRobots>(world, *bus);
    if (cell_bench::has_session(session_dir)) {
      fmt::print("session: reusing {}\n", session_dir.string());
    } else {
      const auto t0 = Clock::now();
      cell_bench::record_session(world, robots->sheet(), session_dir, record_s);
      fmt::print("session: recorded {:.1f} s of {} cameras into {} in {:.1f} s\n", record_s, world.cameras.size(),
                 session_dir.string(), since(t0));
    }
    config = cell_bench::bench_cell_config(cell_path, session_dir, hz, triangles, work);
    config.cell.twin_lockstep = lockstep;
    config.cell.twin_background_factorization = twin_factorisation == "background";
    config.cell.twin_priority = *cell::worker_priority_from_name(twin_priority);  // checked by CLI11
  } catch (const std::exception& e) {
    fmt::print(stderr, "cell_benchmark: {}\n", e.what());
    return 1;
  }
  std::fflush(stdout);

  cell_bench::MemorySampler memory(memory_every_s, warmup_s);  // first sample: warm-up done
  int exit_code = 0;
  {
    robots->start();
    cell::CellController cell(config, *bus);
    if (cell.startup() != cell::CellState::kReady) {
      fmt::print("cell_benchmark: start-up FAILED: {}\n", cell.reason());
      exit_code = 2;
    } else {
      const std::string priority_problem = cell.twin_priority_problem();
      fmt::print("cell_benchmark: READY ({} cameras, pixel stride {}, twin {} triangles, {} Hz, {} OpenMP thread(s), "
                 "twin {}, twin worker priority {}, factorisations {})\n",
                 config.cameras.size(), config.tracker.fusion.pixel_stride, config.sheet.mesh.triangle_count(), hz,
                 threads,
                 lockstep ? "in lockstep" : "at its own pace",
                 priority_problem.empty() ? twin_priority : "normal: " + priority_problem, twin_factorisation);
      std::fflush(stdout);
      const std::string label = fmt::format("cell {}x{}x{} twin {} tris", config.cameras.front().depth_mode.width,
                                            config.cameras.front().depth_mode.height, config.cameras.size(),
                                            config.sheet.mesh.triangle_count());
      std::vector<std::string> phases;
      if (phase != "moving") phases.push_back("still");
      if (phase != "still") phases.push_back("moving");
      const auto run_start = Clock::now();
      cell::CellState last_state = cell::CellState::kReady;
      for (const std::string& name : phases) {
        const int grasp = name == "moving" ? moving_grasp(cell) : -1;
        const std::string gripper = grasp >= 0 ? cell.plan().grasps[grasp].gripper : "";
        const twin::Vec3 hold = grasp >= 0 ? cell.plan().grasps[grasp].hold_position_m : twin::Vec3::Zero();
        if (name == "moving" && grasp < 0) fmt::print("moving phase: no grasp held by an arm; the ply stays still\n");
        bool out = true;  // the goal is hold + sweep (out) or the hold position (back)
        if (!gripper.empty()) cell.set_goal(gripper, twin::Vec3(hold + twin::Vec3(sweep_m, 0, 0)));
        cell_bench::CycleFigures figures;
        const auto phase_start = Clock::now();
        while (since(phase_start) < warmup_s + seconds) {
          if (!gripper.empty() && cell.at_goal(gripper)) {
            out = !out;
            cell.set_goal(gripper, out ? twin::Vec3(hold + twin::Vec3(sweep_m, 0, 0)) : hold);
            figures.count_sweep();
          }
          const std::int64_t cycle_start_us = drivers::host_clock_us();
          const cell::CycleReport r = cell.cycle();
          if (r.state != last_state) {  // say why the cell left RUNNING (the figures include it)
            fmt::print("state: {} at t={:.2f} s{}{}\n", cell::to_string(r.state), since(run_start),
                       cell.reason().empty() ? "" : ": ", cell.reason());
            last_state = r.state;
          }
          if (since(phase_start) >= warmup_s) {
            figures.add(r);
            if (r.tracked) figures.add_tracker_cycle(cell.last_track());
          }
          memory.poll(since(run_start));
          // As cell_controller paces: a period on, just after the cameras' next frame; late: at once.
          const std::int64_t next_us = cell.next_cycle_start_us(cycle_start_us, r);
          while (true) {
            const std::int64_t left_ms = (next_us - drivers::host_clock_us()) / 1000;
            if (left_ms <= 0) break;
            cell.handle_bus(static_cast<int>(left_ms));
          }
        }
        if (!gripper.empty()) cell.set_goal(gripper, hold);
        fmt::print("{}\n", figures.line(label, name));
        fmt::print("{}\n", figures.verdict(hz, lockstep));
        fmt::print("{}\n", figures.tracker_stages_line());
        std::fflush(stdout);
        if (figures.cycles() == 0) exit_code = 3;
      }
      memory.finish(since(run_start));
      fmt::print("robots: {} arm commands followed by the simulated arms\n", robots->commands_accepted());
      cell.stop("benchmark done");
    }
    robots->stop();
  }
  fmt::print("{}\n", cell_bench::load_average_line());
  std::filesystem::remove_all(work);  // the config, and the session unless --session kept it
  return exit_code;
}
