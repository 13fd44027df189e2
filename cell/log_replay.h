#pragma once
// Replay of an lcm-logger log (LCM's event log format, read with lcm::LogFile): every event is
// published on a bus the monitor listens on (normally memq://) and dispatched at once, with the
// monitor clock set to the run's clock at that event, so ages and rates are those of the logged
// run: the event's log timestamp, or, in a run on the fake world's simulation clock, the last
// SIM_CLOCK logged before it. Optionally the events are also played onto another bus (e.g. the
// loopback udpm bus, for lcm-spy or a live monitor), paced by that clock.

#include <cstdint>
#include <string>

#include "drivers/lcm_bus.h"

namespace cell {

struct ReplayStats {
  std::int64_t events = 0;
  std::int64_t republished = 0;  // events the second bus accepted
  std::int64_t first_utime = 0;  // log timestamps of the first and last event (us)
  std::int64_t last_utime = 0;
};

struct ReplayOptions {
  drivers::LcmBus* republish = nullptr;  // also play onto this bus (may be null)
  // Pace of the republished events: 1 = as logged, 2 = twice as fast, 0 = no waiting.
  double speed = 1.0;
};

// Throws std::runtime_error naming the file when it cannot be opened or is not an LCM log.
ReplayStats replay_log(const std::string& log_path, drivers::LcmBus& bus, std::int64_t& clock_utime,
                       const ReplayOptions& options);

}  // namespace cell
