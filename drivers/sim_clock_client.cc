#include "drivers/sim_clock_client.h"

#include <algorithm>
#include <chrono>

#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>

#include "drivers/lcm_channels.h"

namespace drivers {
namespace {

// Wall time: silence of the clock is measured on the wall, whatever the process runs on.
std::int64_t wall_steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

std::optional<ClockSource> clock_source_from_name(std::string_view name) {
  if (name == "wall") return ClockSource::kWall;
  if (name == "sim") return ClockSource::kSim;
  return std::nullopt;
}

const char* to_string(ClockSource source) { return source == ClockSource::kSim ? "sim" : "wall"; }

SimClockClient::SimClockClient(LcmBus& bus, std::string client) : bus_(bus), client_(std::move(client)) {
  last_message_steady_us_ = wall_steady_us();
  subscription_ = bus_.subscribe<prepreg_lcm::sim_clock_t>(
      std::string(channels::kSimClock), [this](const prepreg_lcm::sim_clock_t& msg) {
        time_.set_us(msg.utime);
        reading_.utime = time_.now_us();
        reading_.sim_us = msg.sim_us;
        reading_.real_time_factor = msg.real_time_factor;
        reading_.held = msg.state == prepreg_lcm::sim_clock_t::STATE_HELD;
        reading_.held_by = msg.held_by;
        ++reading_.messages;
        last_message_steady_us_ = wall_steady_us();
      });
}

SimClockClient::~SimClockClient() {
  leave();
  bus_.unsubscribe(subscription_);
}

double SimClockClient::silent_s() const {
  return 1e-6 * static_cast<double>(wall_steady_us() - last_message_steady_us_.load());
}

void SimClockClient::publish_hold(std::int64_t until_us, bool leaving) {
  prepreg_lcm::sim_clock_hold_t msg;
  msg.utime = std::max<std::int64_t>(0, now_us());
  msg.client = client_;
  msg.until_utime = std::max<std::int64_t>(0, until_us);
  msg.leaving = leaving;
  bus_.publish(std::string(channels::kSimClockHold), msg);
}

void SimClockClient::hold(std::int64_t until_us) {
  if (client_.empty() || left_) return;
  publish_hold(until_us, false);
}

bool SimClockClient::advance_to(std::int64_t until_us, double silence_s, const std::atomic<bool>* stop) {
  hold(until_us);
  const std::int64_t waiting_since_us = wall_steady_us();
  std::int64_t held_since_us = waiting_since_us;
  while (reading_.messages == 0 || now_us() < until_us) {
    if (stop && stop->load()) return false;
    // Silence counts from when this wait began: the time this process spent computing since
    // the last SIM_CLOCK (a long start-up, a step) is no sign that the world is gone.
    const std::int64_t heard_us = std::max(last_message_steady_us_.load(), waiting_since_us);
    if (1e-6 * static_cast<double>(wall_steady_us() - heard_us) > silence_s) return false;
    bus_.handle_for(std::chrono::milliseconds(5));
    // Loopback UDP may still drop a datagram: say it again rather than wait for ever.
    if (wall_steady_us() - held_since_us > 500'000) {
      hold(until_us);
      held_since_us = wall_steady_us();
    }
  }
  return true;
}

void SimClockClient::leave() {
  if (client_.empty() || left_) return;
  publish_hold(now_us(), true);
  left_ = true;
}

}  // namespace drivers
