#pragma once
// Faults a simulated D415 produces on demand, as a real one does them (times are simulation
// seconds since activate(); a window [from, until) with until = infinity lasts for ever):
//  - dropped frames: the frame never reaches the host; its sequence number is skipped, and if
//    nothing else arrives within read_timeout, read() returns kTimeout.
//  - frozen stream: the device keeps sending the same image (a hung ISP / USB stream); the
//    sequence counter and device timestamps keep advancing unless frozen_sequence_advances is off.
//  - dead camera: unplugged / firmware crash; read() returns kLost at once (as ENODEV does), and
//    the camera comes back at dead_until_s if that is finite (a later read reopens it).
//  - stale timestamps: kStopped, the device clock stops (every frame carries the timestamp of
//    stale_from_s); kLagging, frames arrive stale_lag_s late (content and device time are that
//    old, host time is now).
//  - bumped camera: knocked on its mount, it sees the cell from its pose moved by
//    (bump_x_m, bump_y_m, bump_z_m) in its own frame while the frames still carry the configured
//    camera_to_cell, as a real one would; only a calibration check can tell.
// The camera only reports what a driver would know (kLost, kTimeout); spotting frozen and stale
// streams is the consumer's job (the generic monitor in drivers/).

#include <cstdint>
#include <limits>

namespace sim_hw {

enum class StaleMode { kStopped, kLagging };

struct D415FaultConfig {
  static constexpr double kNever = std::numeric_limits<double>::infinity();
  double drop_probability = 0.0;  // each frame independently
  int drop_every_nth = 0;         // 0 = off; else frames n-1, 2n-1, ... are dropped
  double drop_from_s = 0.0, drop_until_s = kNever;
  double frozen_from_s = kNever, frozen_until_s = kNever;
  bool frozen_sequence_advances = true;
  double dead_from_s = kNever, dead_until_s = kNever;
  double stale_from_s = kNever, stale_until_s = kNever;
  StaleMode stale_mode = StaleMode::kStopped;
  double stale_lag_s = 1.0;
  double bumped_from_s = kNever, bumped_until_s = kNever;
  double bump_x_m = 0.0, bump_y_m = 0.0, bump_z_m = 0.0;  // camera frame
};

inline bool in_window(double t, double from, double until) { return t >= from && t < until; }

}  // namespace sim_hw
