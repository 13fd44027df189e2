// lcm-logger log -> monitor bus (and optionally a live bus).
#include "cell/log_replay.h"

#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <thread>

namespace cell {

ReplayStats replay_log(const std::string& log_path, drivers::LcmBus& bus, std::int64_t& clock_utime,
                       const ReplayOptions& options) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("LCM log " + log_path + ": cannot open for reading");
  ReplayStats stats;
  const auto wall_start = std::chrono::steady_clock::now();
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (stats.events == 0) stats.first_utime = event->timestamp;
    stats.last_utime = event->timestamp;
    ++stats.events;
    clock_utime = event->timestamp;
    if (options.republish) {
      if (options.speed > 0.0) {
        const auto due = wall_start + std::chrono::microseconds(static_cast<std::int64_t>(
                                          (event->timestamp - stats.first_utime) / options.speed));
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
