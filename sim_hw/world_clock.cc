#include "sim_hw/world_clock.h"

#include <algorithm>

#include <fmt/core.h>
#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>

#include "drivers/lcm_channels.h"

namespace sim_hw {

using Wall = std::chrono::steady_clock;

WorldClock::WorldClock(WorldClockOptions options, drivers::LcmBus& bus) : options_(std::move(options)), bus_(bus) {
  // The wall's epoch time (the process is on simulation time already: process_time_).
  epoch_us_ = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
                  .count();
  for (const std::string& name : options_.lockstep) clients_[name] = Client{0, false, Wall::now()};
  process_time_.set_us(epoch_us_);
  anchor_wall_ = rate_wall_ = Wall::now();  // last_held_publish_: never, so the first hold is told at once
  subscription_ = bus_.subscribe<prepreg_lcm::sim_clock_hold_t>(
      std::string(drivers::channels::kSimClockHold), [this](const prepreg_lcm::sim_clock_hold_t& msg) {
        const auto it = clients_.find(msg.client);
        if (it == clients_.end()) return;  // not one we wait for (or one already let go)
        if (msg.leaving) {
          clients_.erase(it);
          return;
        }
        Client& c = it->second;
        c.until_us = std::max(c.until_us, msg.until_utime - epoch_us_);
        c.heard = true;
        c.last_heard = Wall::now();
      });
}

WorldClock::~WorldClock() { bus_.unsubscribe(subscription_); }

std::int64_t WorldClock::limit_us() {
  std::int64_t limit = kUnlimited;
  held_by_.clear();
  const auto now = Wall::now();
  for (auto it = clients_.begin(); it != clients_.end();) {
    Client& c = it->second;
    const bool waiting_on_it = c.until_us <= sim_us_;
    if (waiting_on_it && c.heard && std::chrono::duration<double>(now - c.last_heard).count() > options_.client_silence_s) {
      notice_ = fmt::format("lockstep client {} silent for {:.0f} s while the clock waited on it: running on without it",
                            it->first, options_.client_silence_s);
      ++clients_dropped_;
      it = clients_.erase(it);
      continue;
    }
    if (c.until_us < limit) {
      limit = c.until_us;
      held_by_ = c.heard ? it->first : it->first + " (not heard yet)";
    }
    ++it;
  }
  return limit;
}

std::string WorldClock::held_by() const { return held_by_; }

bool WorldClock::pace_to(std::int64_t target_us, const std::atomic<bool>* stop) {
  if (options_.max_real_time_factor <= 0) return !(stop && stop->load());
  const auto now = Wall::now();
  const auto due = anchor_wall_ + std::chrono::duration_cast<Wall::duration>(std::chrono::duration<double>(
                                      1e-6 * static_cast<double>(target_us - anchor_sim_us_) / options_.max_real_time_factor));
  if (due <= now) {
    // Behind (slow physics, or a client held us): run on from now, never catch up faster than the limit.
    anchor_wall_ = now;
    anchor_sim_us_ = target_us;
    return !(stop && stop->load());
  }
  while (Wall::now() < due) {
    if (stop && stop->load()) return false;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(due - Wall::now());
    bus_.handle_for(std::clamp(left, std::chrono::milliseconds(1), std::chrono::milliseconds(5)));
  }
  return !(stop && stop->load());
}

void WorldClock::advance_to(std::int64_t target_us) {
  if (target_us <= sim_us_) return;
  sim_us_ = target_us;
  process_time_.set_us(utime());
  update_rate();
}

void WorldClock::wait_held(std::chrono::milliseconds wait) {
  const auto now = Wall::now();
  if (now - last_held_publish_ >= std::chrono::milliseconds(100)) {
    update_rate();
    publish(true);
    last_held_publish_ = now;
  }
  bus_.handle_for(std::max(wait, std::chrono::milliseconds(1)));
}

void WorldClock::update_rate() {
  const auto now = Wall::now();
  const double wall_s = std::chrono::duration<double>(now - rate_wall_).count();
  if (wall_s >= 1.0) {
    real_time_factor_ = 1e-6 * static_cast<double>(sim_us_ - rate_sim_us_) / wall_s;
    rate_wall_ = now;
    rate_sim_us_ = sim_us_;
  }
}

void WorldClock::publish(bool held) {
  prepreg_lcm::sim_clock_t msg;
  msg.utime = utime();
  msg.sim_us = sim_us_;
  msg.real_time_factor = real_time_factor_;
  msg.state = held ? prepreg_lcm::sim_clock_t::STATE_HELD : prepreg_lcm::sim_clock_t::STATE_RUNNING;
  msg.held_by = held ? held_by_ : std::string();
  bus_.publish(std::string(drivers::channels::kSimClock), msg);
}

std::string WorldClock::take_notice() { return std::exchange(notice_, std::string()); }

}  // namespace sim_hw
