// monitor_cycle_publisher: publishes made-up cell cycles (tests/cell/cycle_messages.h) on an LCM
// URL at a fixed rate, plus one undecodable message first (unless --no-malformed), for the udpm
// monitor test and for looking at our types in lcm-spy. Cycle 3 reports cam_right lost.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <random>
#include <thread>

#include "drivers/lcm_channels.h"
#include "tests/cell/cycle_messages.h"

int main(int argc, char** argv) {
  CLI::App app{"Publish made-up cell cycles on LCM (test support)."};
  std::string url = drivers::kLoopbackLcmUrl;
  int cycles = 20;
  double hz = 20.0, delay_s = 0.0;
  bool no_malformed = false;
  int grid = 12;
  app.add_option("--lcm", url, "LCM URL");
  app.add_option("--cycles", cycles, "cycles to publish (0: until killed)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--hz", hz, "cycle rate")->check(CLI::PositiveNumber);
  app.add_option("--delay-s", delay_s, "wait before the first cycle (let listeners start)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--grid", grid, "sheet vertices per side")->check(CLI::Range(2, 1000));
  app.add_flag("--no-malformed", no_malformed,
               "skip the undecodable message (lcm-spy types a channel by its first message)");
  CLI11_PARSE(app, argc, argv);
  try {
    drivers::LcmBus bus(url);
    std::this_thread::sleep_for(std::chrono::duration<double>(delay_s));
    std::mt19937 rng(5);
    const std::uint8_t garbage[] = {0xde, 0xad, 0xbe, 0xef};
    if (!no_malformed) {
      bus.publish_raw(std::string(drivers::channels::kPredictionError), garbage, sizeof garbage);
    }
    const auto period = std::chrono::duration<double>(1.0 / hz);
    auto next = std::chrono::steady_clock::now();
    for (int id = 0; cycles == 0 || id < cycles; ++id) {
      const auto c = testing_support::make_cycle(id, drivers::utime_now(), rng, grid,
                                                 id == 3 ? "cam_right" : "");
      if (!testing_support::publish_cycle(bus, c)) {
        fmt::print(stderr, "publish failed: {}\n", bus.last_problem());
        return 1;
      }
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      std::this_thread::sleep_until(next);
    }
    fmt::print("published {} cycles on {}\n", cycles, url);
  } catch (const std::exception& e) {
    fmt::print(stderr, "monitor_cycle_publisher: {}\n", e.what());
    return 1;
  }
  return 0;
}
