// lcm-logger log -> monitor bus (and optionally a live bus).
#include "cell/log_replay.h"

#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <thread>

#include <prepreg_lcm/sim_clock_t.hpp>

#include "drivers/lcm_channels.h"
#include "drivers/lcm_message_checks.h"

namespace cell {

ReplayStats replay_log(const std::string& log_path, drivers::LcmBus& bus, std::int64_t& clock_utime,
                       const ReplayOptions& options) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("LCM log " + log_path + ": cannot open for reading");
  ReplayStats stats;
  const auto wall_start = std::chrono::steady_clock::now();
  std::int64_t sim_utime = -1;  // the run's simulation clock, once a SIM_CLOCK was logged
  std::int64_t first_clock_utime = 0;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (stats.events == 0) stats.first_utime = event->timestamp;
    stats.last_utime = event->timestamp;
    if (event->channel == drivers::channels::kSimClock) {
      prepreg_lcm::sim_clock_t m;
      if (event->datalen > 0 && m.decode(event->data, 0, event->datalen) == event->datalen &&
          drivers::message_problem(m).empty()) {
        sim_utime = std::max(sim_utime, m.utime);
      }
    }
    // The clock the run ran on: the logger stamps events on the wall as they arrive, but a run on
    // the fake world's simulation clock lived on SIM_CLOCK's time.
    clock_utime = sim_utime >= 0 ? sim_utime : event->timestamp;
    if (stats.events == 0) first_clock_utime = clock_utime;
    ++stats.events;
    if (options.republish) {
      if (options.speed > 0.0) {
        if (clock_utime < first_clock_utime) first_clock_utime = clock_utime;  // the clock switched
        const auto due = wall_start + std::chrono::microseconds(static_cast<std::int64_t>(
                                          (clock_utime - first_clock_utime) / options.speed));
        std::this_thread::sleep_until(due);
      }
      if (options.republish->publish_raw(event->channel, event->data,
                                         static_cast<std::size_t>(event->datalen))) {
        ++stats.republished;
      }
    }
    bus.publish_raw(event->channel, event->data, static_cast<std::size_t>(event->datalen));
    // memq delivers synchronously on handle: dispatch until this event is consumed.
    while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
    }
  }
  if (stats.events == 0) {
    throw std::runtime_error("LCM log " + log_path + ": no events (empty or not an LCM log)");
  }
  return stats;
}

}  // namespace cell
