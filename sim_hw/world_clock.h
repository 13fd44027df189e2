#pragma once
// The fake world's simulation clock, the master of SIM_CLOCK (prepreg_lcm::sim_clock_t): the
// world advances its time event by event, as fast as its physics and cameras allow and never
// faster than max_real_time_factor times the wall; it publishes each advance, and about ten
// times a wall second while it is held so that its clients can tell "held" from "gone".
//
// Lockstep: every client named in `lockstep` (the cell controller) holds the clock with
// SIM_CLOCK_HOLD (prepreg_lcm::sim_clock_hold_t): the clock never passes a client's last
// until_utime, and waits at 0 for a client it has not heard yet. A client that leaves is let go;
// one that, once heard, sends nothing for client_silence_s of wall time while the clock waits
// on it is dropped with a message (a crashed controller must not freeze the world).
//
// Times: the clock counts whole microseconds since the world started (sim_us), so event times
// do not drift; utime = the wall's epoch time at construction + sim_us. The process runs on its
// own clock (common/process_clock.h), so every message the world stamps carries simulation time.
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "common/process_clock.h"
#include "drivers/lcm_bus.h"

namespace sim_hw {

struct WorldClockOptions {
  double max_real_time_factor = 1.0;  // 0: no limit (as fast as the physics allows)
  std::vector<std::string> lockstep;   // clients the clock waits for, from the start
  double client_silence_s = 30.0;      // wall seconds a waiting client may stay silent
};

class WorldClock {
 public:
  static constexpr std::int64_t kUnlimited = std::numeric_limits<std::int64_t>::max();

  // Subscribes to SIM_CLOCK_HOLD on `bus` (handled on the caller's thread, with the world's
  // other subscriptions) and puts the process on simulation time. Throws std::logic_error when
  // the process already runs on simulation time.
  WorldClock(WorldClockOptions options, drivers::LcmBus& bus);
  ~WorldClock();
  WorldClock(const WorldClock&) = delete;
  WorldClock& operator=(const WorldClock&) = delete;

  std::int64_t sim_us() const { return sim_us_; }
  double sim_s() const { return 1e-6 * static_cast<double>(sim_us_); }
  std::int64_t utime() const { return epoch_us_ + sim_us_; }
  std::int64_t epoch_us() const { return epoch_us_; }

  // How far the clock may run now (sim_us; kUnlimited without lockstep clients) and who sets it.
  std::int64_t limit_us();
  std::string held_by() const;
  // Waits on the wall until the rate limit lets the clock reach sim_us, handling the bus
  // meanwhile (holds and commands keep arriving). False when *stop was set first.
  bool pace_to(std::int64_t sim_us, const std::atomic<bool>* stop);
  // Moves the clock (never back); publish() tells the bus, once that time's work is done.
  void advance_to(std::int64_t sim_us);
  void publish(bool held);
  // While held: handles the bus for up to `wait` and publishes the clock as HELD about ten
  // times a wall second.
  void wait_held(std::chrono::milliseconds wait);

  double real_time_factor() const { return real_time_factor_; }
  std::uint64_t clients_dropped() const { return clients_dropped_; }
  // What the clock has to say (a client dropped for silence); empty when nothing. Cleared by reading.
  std::string take_notice();

 private:
  struct Client {
    std::int64_t until_us = 0;  // sim_us it may reach
    bool heard = false;
    std::chrono::steady_clock::time_point last_heard;
  };
  void update_rate();

  WorldClockOptions options_;
  drivers::LcmBus& bus_;
  drivers::LcmBus::SubscriptionId subscription_ = -1;
  prepreg::SimulatedTime process_time_;
  std::int64_t epoch_us_ = 0;
  std::int64_t sim_us_ = 0;
  std::map<std::string, Client> clients_;  // the lockstep clients still held for
  std::string held_by_;
  std::uint64_t clients_dropped_ = 0;
  std::string notice_;
  // Rate limit: the wall time at which sim time anchor_sim_us_ was reached.
  std::chrono::steady_clock::time_point anchor_wall_;
  std::int64_t anchor_sim_us_ = 0;
  // Real-time factor over about a wall second.
  std::chrono::steady_clock::time_point rate_wall_;
  std::int64_t rate_sim_us_ = 0;
  double real_time_factor_ = 0.0;
  std::chrono::steady_clock::time_point last_held_publish_;
};

}  // namespace sim_hw
