#pragma once
// A process of the cell on the fake world's simulation clock (SIM_CLOCK, prepreg_lcm::sim_clock_t):
// the cell config's "clock": "sim". While a SimClockClient is alive the process runs on
// simulation time (common/process_clock.h): drivers::host_clock_us() and drivers::utime_now()
// both return the last SIM_CLOCK's utime, so cycle pacing, watchdogs, frame arrival stamps and
// message stamps follow the world without knowing it.
//
// A lockstep client (the cell controller) also holds the world (SIM_CLOCK_HOLD,
// prepreg_lcm::sim_clock_hold_t): the world never runs past the client's last hold, so the
// client may compute as long as it needs and a run repeats exactly whatever the machine's speed
// (Gazebo's lockstep, Drake's simulator time). Real hardware runs on "clock": "wall".
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/process_clock.h"
#include "drivers/lcm_bus.h"

namespace drivers {

enum class ClockSource { kWall, kSim };
std::optional<ClockSource> clock_source_from_name(std::string_view name);  // "wall", "sim"
const char* to_string(ClockSource source);

struct SimClockReading {
  std::int64_t utime = 0;  // 0: no SIM_CLOCK yet
  std::int64_t sim_us = 0;  // since the world started
  double real_time_factor = 0;
  bool held = false;
  std::string held_by;
  std::int64_t messages = 0;
};

class SimClockClient {
 public:
  // Subscribes to SIM_CLOCK on `bus` and puts the process on simulation time. `client` empty:
  // follow only (a monitor); else the name the world's --lockstep knows it by. The bus's handling
  // thread is the caller's (LcmBus rules). Throws std::logic_error when the process already runs
  // on simulation time.
  SimClockClient(LcmBus& bus, std::string client);
  ~SimClockClient();  // leaves (a lockstep client) and unsubscribes
  SimClockClient(const SimClockClient&) = delete;
  SimClockClient& operator=(const SimClockClient&) = delete;

  std::int64_t now_us() const { return time_.now_us(); }
  const SimClockReading& reading() const { return reading_; }
  const std::string& client() const { return client_; }
  // Wall seconds since the last SIM_CLOCK (since construction before the first). The world sends
  // it while held too, so a long silence means the world is gone.
  double silent_s() const;

  // Lets the clock run to until_us: publishes the hold (a lockstep client; a follower only
  // waits) and handles the bus until the clock has reached it. False when the clock fell silent
  // for silence_s of wall time during this wait (time spent computing before it does not
  // count), or *stop was set.
  bool advance_to(std::int64_t until_us, double silence_s, const std::atomic<bool>* stop = nullptr);
  // Publishes the hold without waiting.
  void hold(std::int64_t until_us);
  // A lockstep client stops holding the world (also done by the destructor).
  void leave();

 private:
  void publish_hold(std::int64_t until_us, bool leaving);

  LcmBus& bus_;
  std::string client_;
  prepreg::SimulatedTime time_;
  LcmBus::SubscriptionId subscription_ = -1;
  SimClockReading reading_;  // the handling thread's
  std::atomic<std::int64_t> last_message_steady_us_{0};
  bool left_ = false;
};

}  // namespace drivers
