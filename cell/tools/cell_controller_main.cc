// cell_controller: the cell's controller process (issue 5). Reads the cell config, runs the
// start-up sequence (cameras, material, grasp plan, robots, twin, first tracked frame and
// calibration check) and then cycles at cell.cycle_hz: cameras -> tracker -> twin -> LCM
// (SHEET_OBSERVED, SHEET_PREDICTED, PREDICTION_ERROR, CAMERA_STATUS_<CAM>, CELL_STATE) ->
// robot commands, under the watchdog. After READY it runs the experiment file of the config's
// job (unless --no-experiment) and prints its table. One status line per second.
//
//   cell_controller --config CELL.json [--lcm URL] [--out DIR] [--max-seconds S]
//                   [--no-experiment] [--exit-after-experiment] [--fault-injection] [--quiet]
//                   [--threads N]
//
// Exit codes: 0 stopped on request (SIGINT/SIGTERM), after --max-seconds or after the experiment,
// in RUNNING or DEGRADED; 1 config error (file or field named); 2 start-up FAILED (reason
// printed and on CELL_STATE); 3 in SAFE_HOLD when it stopped; 4 --exit-after-experiment was
// given but the experiment did not finish within --max-seconds.
#include <cstdio>
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <fmt/core.h>

#include <algorithm>
#include <omp.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <vector>

#include "cell/cell_config.h"
#include "cell/cell_controller.h"
#include "cell/experiment_runner.h"
#include "twin/base/atomic_file.h"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))];
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // status lines reach a log file as they happen
  CLI::App app{"The prepreg layup cell's controller: start-up, per-cycle tracking and twin, robots"};
  std::string config_path, lcm_url, out_dir, material_path;
  double max_seconds = 0;
  bool no_experiment = false, exit_after = false, fault_injection = false, quiet = false;
  app.add_option("--config", config_path, "cell config JSON (cell, twin, job, tracker, cameras, arms, grippers)")->required();
  app.add_option("--lcm", lcm_url, "LCM URL (default: the config's cell.lcm_url)");
  app.add_option("--out", out_dir, "write DIR/experiment.json here");
  app.add_option("--material", material_path,
                 "material file to run instead of the config's twin.material_file (e.g. one the cell learned)")
      ->check(CLI::ExistingFile);
  app.add_option("--max-seconds", max_seconds, "stop after this many seconds of cycling (0: until signalled)");
  app.add_flag("--no-experiment", no_experiment, "do not run the config's experiment; hold the ply");
  app.add_flag("--exit-after-experiment", exit_after, "stop when the experiment is done");
  app.add_flag("--fault-injection", fault_injection,
               "FAKE HARDWARE ONLY: obey SIM_FAULT {target \"twin\", fault \"diverge\"} by making the twin's "
               "step fail until the fault is cleared (without this flag SIM_FAULT is ignored)");
  app.add_flag("--quiet", quiet, "no per-second status line");
  int threads = 1;
  app.add_option("--threads", threads,
                 "OpenMP threads of the tracker and the twin (default 1: the camera threads need the "
                 "other core; with 2 on a busy 2-core machine the twin's step went from 1 ms to 215 ms)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  // The tracker and the twin run on this thread; their parallel regions take this many threads.
  omp_set_num_threads(threads);

  cell::CellConfig config;
  cell::Experiment experiment;
  try {
    config = cell::read_cell_config(config_path);
    if (!lcm_url.empty()) config.cell.lcm_url = lcm_url;
    if (!material_path.empty()) config.material_file = material_path;
    if (!no_experiment && !config.experiment_file.empty()) experiment = cell::read_experiment(config.experiment_file);
    // The fake world's emulated cameras stamp their frames on its simulation clock: on the wall
    // every frame would look stale, so say why instead.
    if (const char* clock = std::getenv("PREPREG_V4L2_EMULATION_CLOCK");
        clock && std::string(clock) == "sim" && config.cell.clock != drivers::ClockSource::kSim) {
      throw std::runtime_error(config_path + ": the fake world's cameras run on its simulation clock "
                               "(PREPREG_V4L2_EMULATION_CLOCK=sim): set cell.clock to \"sim\"");
    }
    if (!out_dir.empty()) twin::create_directories_durably(out_dir);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cell_controller: config error: {}\n", e.what());
    return 1;
  }
  std::unique_ptr<drivers::LcmBus> bus;
  try {
    bus = std::make_unique<drivers::LcmBus>(config.cell.lcm_url);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cell_controller: config error: {}\n", e.what());
    return 1;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  cell::CellController cell(config, *bus, fault_injection);
  if (!out_dir.empty()) cell.set_learning_directory((std::filesystem::path(out_dir) / "learning").string());
  fmt::print("cell_controller: STARTING ({} cameras, {} arms, LCM {}, clock {})\n", config.cameras.size(),
             config.hardware.arms.size(), config.cell.lcm_url, drivers::to_string(config.cell.clock));
  std::fflush(stdout);
  if (const std::string why = cell.twin_priority_problem(); !why.empty()) {
    fmt::print("cell_controller: note: the twin's worker runs at normal priority ({})\n", why);
  }
  if (cell.startup() != cell::CellState::kReady) {
    fmt::print("cell_controller: FAILED: {}\n", cell.reason());
    return 2;
  }
  fmt::print("cell_controller: READY\n");
  std::fflush(stdout);

  std::optional<cell::ExperimentRunner> runner;
  if (!experiment.states.empty()) runner.emplace(experiment);
  const auto start = std::chrono::steady_clock::now();
  auto last_line = start;
  std::vector<double> latency, twin_ms;
  double error_mean = 0, error_max = 0;
  int cycles_in_line = 0, camera_ok = 0, max_substeps = 0;
  bool experiment_printed = false;
  int calibrations_printed = 0, diagnoses_printed = 0, reseeds_printed = 0;
  while (!g_stop) {
    const std::int64_t cycle_start_us = drivers::host_clock_us();
    const cell::CycleReport r = cell.cycle();
    if (runner) runner->on_cycle(cell, r);
    ++cycles_in_line;
    // On the simulation clock the world waits for the cycle, so a frame is as old in simulated
    // time when the cycle ends as when it began: the wall time the cycle took is what it costs.
    if (cell.sim_clock()) latency.push_back(r.cycle_ms);
    else if (r.latency_ms >= 0) latency.push_back(r.latency_ms);
    if (r.twin_stepped) twin_ms.push_back(r.twin_step_ms);
    max_substeps = std::max(max_substeps, r.twin_substeps);
    if (r.tracked) {
      error_mean = r.error.mean_m;
      error_max = r.error.max_m;
    }
    camera_ok = r.frames;
    const auto now = std::chrono::steady_clock::now();
    if (!quiet && now - last_line >= std::chrono::seconds(1)) {
      const double s = std::chrono::duration<double>(now - last_line).count();
      fmt::print("{:8.1f} s  {:<9} {:5.1f} Hz  {} p50 {:5.1f} p99 {:5.1f} ms  error mean {:5.1f} max {:5.1f} mm  "
                 "cameras {}/{}  twin step {:4.1f} ms (sub-steps <= {}){}  {}{}{}\n",
                 std::chrono::duration<double>(now - start).count(), cell::to_string(r.state), cycles_in_line / s,
                 cell.sim_clock() ? "cycle (wall)" : "latency",
                 percentile(latency, 0.5), percentile(latency, 0.99), 1e3 * error_mean, 1e3 * error_max, camera_ok,
                 config.cameras.size(), percentile(twin_ms, 0.5), max_substeps,
                 cell.sim_clock() ? fmt::format("  sim t {:.1f} s rtf {:.2f}", 1e-6 * cell.sim_clock()->reading().sim_us,
                                                cell.sim_clock()->reading().real_time_factor)
                                  : std::string(),
                 runner ? runner->current() : "",
                 cell.reason().empty() ? "" : "  reason: ", cell.reason());
      std::fflush(stdout);
      last_line = now;
      cycles_in_line = 0;
      latency.clear();
      twin_ms.clear();
      max_substeps = 0;
    }
    if (cell.reseed_attempts() > reseeds_printed) {
      reseeds_printed = cell.reseed_attempts();
      const cell::learning::BranchCandidate& rs = *cell.last_reseed();
      fmt::print("{:8.1f} s  branch following: {} ({:.1f} mm mean from the settled sheet, {:.1f} mm from the "
                 "equilibrium found near it){}{}\n",
                 std::chrono::duration<double>(now - start).count(),
                 cell.last_reseed_taken() ? "twin re-seeded from the tracked sheet" : "twin kept its state",
                 1e3 * rs.before_m, 1e3 * rs.after_m, rs.problem.empty() ? "" : ": ", rs.problem);
      std::fflush(stdout);
    }
    if (cell.calibrations() > calibrations_printed) {
      calibrations_printed = cell.calibrations();
      const cell::learning::CalibrationResult& c = *cell.last_calibration();
      fmt::print("{:8.1f} s  calibration {}: {} ({} states fitted, {:.1f} s): {}\n",
                 std::chrono::duration<double>(now - start).count(), calibrations_printed,
                 cell::learning::verdict_name(c.verdict), c.fitted_states, c.seconds, c.reason);
      std::fflush(stdout);
    }
    if (cell.diagnoses() > diagnoses_printed) {
      diagnoses_printed = cell.diagnoses();
      const cell::learning::DiagnosisResult& d = *cell.last_diagnosis();
      fmt::print("{:8.1f} s  diagnosis {}: {}, effect {} ({} states, {:.1f} s): {}\n",
                 std::chrono::duration<double>(now - start).count(), diagnoses_printed,
                 d.ran ? d.outcome.verdict.verdict : "failed", cell::learning::adoption_name(d.adoption), d.states,
                 d.seconds, d.reason);
      std::fflush(stdout);
    }
    if (runner && runner->done() && !experiment_printed) {
      experiment_printed = true;
      fmt::print("\nexperiment ({}):\n{}\n", config.experiment_file, cell::format_results(runner->results()));
      if (!out_dir.empty()) {
        // Atomically: a reader that polls for the file (the integration test, a shop-floor
        // script) must never find it empty or half written (seen in CI).
        const std::filesystem::path results = std::filesystem::path(out_dir) / "experiment.json";
        try {
          twin::write_file_atomically(results, [&](std::ostream& out) {
            out << cell::results_json(runner->results()).dump(2) << "\n";
          });
        } catch (const std::exception& e) {
          fmt::print(stderr, "cell_controller: could not write {}: {}\n", results.string(), e.what());
        }
      }
      if (exit_after) break;
    }
    if (max_seconds > 0 && std::chrono::duration<double>(now - start).count() >= max_seconds) break;
    // Sleep to the next start while dispatching LCM: a period on, just after the cameras' next
    // frame (cell/cycle_pacer.h); a late cycle starts the next at once.
    // On the simulation clock the world waits here for the cycle, and runs on to next_us.
    cell.wait_until(cell.next_cycle_start_us(cycle_start_us, r), &g_stop);
  }
  const cell::CellState final_state = cell.state();
  cell.stop(g_stop ? "stopped by signal" : "stopped");
  if (!out_dir.empty()) {
    // What the cameras saw, as a trial: `twin identify --train DIR` / `twin diagnose` take it.
    const std::string trial_dir = (std::filesystem::path(out_dir) / "observed_trial").string();
    const std::string why = cell.write_observed_trial(trial_dir);
    if (why.empty()) {
      fmt::print("cell_controller: {} settled states written as a trial: {}\n", cell.settled_states().states().size(),
                 trial_dir);
    } else {
      fmt::print("cell_controller: no observed trial written ({})\n", why);
    }
  }
  fmt::print("cell_controller: STOPPED (was {}; {} malformed messages dropped)\n", cell::to_string(final_state),
             cell.dropped_messages());
  const int status = final_state == cell::CellState::kSafeHold ? 3 : (exit_after && runner && !runner->done()) ? 4 : 0;
  // A calibration or branch candidate still running was told to stop; at idle priority on a
  // machine another process keeps busy (the fake world) it may not get the CPU to notice for
  // minutes. Its results are not needed any more and everything the run made is written: end
  // without waiting for it (and without running destructors under it).
  if (!cell.shut_down_background(std::chrono::seconds(2))) {
    fmt::print("cell_controller: background learning still running at exit, abandoned\n");
    cell::restore_normal_priority_of_all_threads();  // so that its threads end with the process
    std::fflush(stdout);
    std::fflush(stderr);
    std::_Exit(status);
  }
  return status;
}
