// replay_cell_log: reads an lcm-logger log of a cell run and prints it through the monitor, with
// the prediction error recomputed from the logged SHEET_OBSERVED and SHEET_PREDICTED beside the
// logged PREDICTION_ERROR. Exit status: 0 all agree, 1 bad input, 2 some cycles disagree.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "cell/cell_monitor.h"
#include "cell/log_replay.h"
#include "cell/monitor_format.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Replay an lcm-logger log of a cell run through the monitor, checking the logged "
      "prediction error against the tracker's metric."};
  std::string log_path, republish_url;
  int every = 1;
  double speed = 1.0;
  app.add_option("LOG", log_path, "lcm-logger log file")->required();
  app.add_option("--every", every, "print every Nth cycle (state changes always)")
      ->check(CLI::PositiveNumber);
  app.add_option("--republish", republish_url,
                 "also play the log onto this LCM URL (e.g. udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--speed", speed, "republish pace: 1 as logged, 0 as fast as possible")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);

  try {
    drivers::LcmBus bus("memq://");
    std::unique_ptr<drivers::LcmBus> republish;
    if (!republish_url.empty()) republish = std::make_unique<drivers::LcmBus>(republish_url);
    std::int64_t clock_utime = 0;
    std::int64_t printed = 0;
    cell::MonitorSinks sinks;
    sinks.cycle = [&](const cell::CycleRecord& r) {
      if (printed++ % every == 0) fmt::print("{}\n", cell::format_cycle(r));
    };
    sinks.state_change = [](const cell::StateChange& c) {
      fmt::print("{}\n", cell::format_state_change(c));
    };
    cell::CellMonitor monitor(bus, cell::MonitorOptions{}, sinks, [&] { return clock_utime; });
    cell::ReplayOptions options;
    options.republish = republish.get();
    options.speed = speed;
    const cell::ReplayStats stats = cell::replay_log(log_path, bus, clock_utime, options);
    monitor.flush();
    fmt::print(
        "replayed {} events over {:.2f} s of log{}\n", stats.events,
        1e-6 * static_cast<double>(stats.last_utime - stats.first_utime),
        republish ? fmt::format(", {} republished on {}", stats.republished, republish_url) : "");
    fmt::print("{}", cell::format_summary(monitor.summary(), bus.counters()));
    return monitor.summary().mismatches() > 0 ? 2 : 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "replay_cell_log: {}\n", e.what());
    return 1;
  }
}
