// cell_monitor: a terminal view of the running cell, one line per cycle (state, prediction error,
// coverage, latency, cameras, device status ages, dropped messages) and a summary at exit.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>

#include "cell/cell_monitor.h"
#include "cell/monitor_format.h"
#include "drivers/sim_clock_client.h"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Terminal monitor of the cell's LCM bus: a line per cycle, a summary at exit."};
  std::string url = drivers::kLoopbackLcmUrl;
  double max_seconds = 0.0;
  int every = 1;
  bool summary = false, no_recompute = false, sim_clock = false;
  app.add_option("--lcm", url, "LCM URL (default: loopback udpm, ttl=0)");
  app.add_option("--max-seconds", max_seconds, "exit after this many seconds (0: until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--every", every, "print every Nth cycle (state changes always)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--summary", summary, "print a summary at exit");
  app.add_flag("--no-recompute", no_recompute,
               "do not recompute the error from SHEET_OBSERVED/SHEET_PREDICTED");
  app.add_flag("--sim-clock", sim_clock,
               "run on the fake world's SIM_CLOCK (a cell on \"clock\": \"sim\"): device ages and the "
               "cycle rate in simulation time");
  CLI11_PARSE(app, argc, argv);

  try {
    drivers::LcmBus bus(url);
    // Before the monitor: its clock is the process's (drivers::utime_now).
    std::optional<drivers::SimClockClient> clock;
    if (sim_clock) clock.emplace(bus, "");
    cell::MonitorOptions options;
    options.recompute = !no_recompute;
    std::int64_t printed = 0;
    cell::MonitorSinks sinks;
    sinks.cycle = [&](const cell::CycleRecord& r) {
      if (printed++ % every == 0) fmt::print("{}\n", cell::format_cycle(r));
      std::fflush(stdout);
    };
    sinks.calibration = [](const cell::CalibrationEvent& e) {
      fmt::print("{}\n", cell::format_calibration(e));
      std::fflush(stdout);
    };
    sinks.diagnosis = [](const cell::DiagnosisEvent& e) {
      fmt::print("{}\n", cell::format_diagnosis(e));
      std::fflush(stdout);
    };
    sinks.state_change = [](const cell::StateChange& c) {
      fmt::print("{}\n", cell::format_state_change(c));
      std::fflush(stdout);
    };
    cell::CellMonitor monitor(bus, options, sinks);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    // Subscribed from here on: scripts (tests/cell/udpm_monitor_test.sh) wait for this line
    // before they publish, and an operator sees which bus is watched.
    fmt::print(stderr, "cell_monitor: listening on {}\n", url);
    const auto start = std::chrono::steady_clock::now();
    while (!g_stop) {
      if (max_seconds > 0 &&
          std::chrono::steady_clock::now() - start >= std::chrono::duration<double>(max_seconds)) {
        break;
      }
      bus.handle_for(std::chrono::milliseconds(100));
    }
    // Messages that arrived before the stop (a signal may cut the last wait short) still count:
    // a script that stops the monitor once its publisher has exited gets every cycle published.
    while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
    }
    monitor.flush();
    if (summary) fmt::print("{}", cell::format_summary(monitor.summary(), bus.counters()));
  } catch (const std::exception& e) {
    fmt::print(stderr, "cell_monitor: {}\n", e.what());
    return 1;
  }
  return 0;
}
