#include "sim_hw/emulated_camera_rig.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sim_hw {
namespace {

SimulatedD415Options options_for(const WorldCamera& camera, SceneSource scene) {
  SimulatedD415Options o;
  o.scene = std::move(scene);
  o.noise = camera.noise;
  o.seed = camera.seed;
  o.clock = SimClock::kSimulated;  // the world's clock: each read renders the next frame at once
  return o;
}

}  // namespace

EmulatedCameraRig::EmulatedCameraRig(const WorldCamera& camera, SceneSource scene)
    : camera_(camera), d415_(options_for(camera, std::move(scene))) {
  drivers::DriverResult r = d415_.configure(camera_.config);
  if (r.ok) r = d415_.activate();
  if (!r.ok) throw std::runtime_error("camera " + camera_.config.name + ": " + r.message);
  bridge_ = std::make_unique<V4l2CameraBridge>(d415_, camera_.config, camera_.node_prefix);
}

EmulatedCameraRig::~EmulatedCameraRig() = default;

void EmulatedCameraRig::serve_frame() {
  const drivers::ReadStatus s = bridge_->pump();
  if (s == drivers::ReadStatus::kFrame) ++frames_;
  if (s == drivers::ReadStatus::kLost) ++lost_;
  // The camera's own time is the frame it last made (a dropped frame moves it on by a period, a
  // timeout to its deadline); its next frame is a period after that and never before the next
  // one the world expected.
  const std::int64_t period_us = std::llround(1e6 / std::max(1, camera_.config.depth_mode.fps));
  const std::int64_t camera_us = std::llround(d415_.sim_time_s() * 1e6);
  next_frame_us_ = std::max(next_frame_us_, camera_us) + period_us;
}

bool EmulatedCameraRig::apply_fault(const std::string& fault, bool active, double t) {
  D415FaultConfig f = d415_.faults();
  const double never = D415FaultConfig::kNever;
  if (fault == "dead") {
    if (active) f.dead_from_s = t, f.dead_until_s = never;
    else f.dead_until_s = std::min(f.dead_until_s, t);
  } else if (fault == "frozen") {
    if (active) f.frozen_from_s = t, f.frozen_until_s = never;
    else f.frozen_until_s = std::min(f.frozen_until_s, t);
  } else if (fault == "stale") {
    if (active) f.stale_from_s = t, f.stale_until_s = never, f.stale_mode = StaleMode::kStopped;
    else f.stale_until_s = std::min(f.stale_until_s, t);
  } else if (fault == "drop") {
    if (active) f.drop_probability = 0.5, f.drop_from_s = t, f.drop_until_s = never;
    else f.drop_until_s = std::min(f.drop_until_s, t);
  } else if (fault == "bumped") {
    // Knocked 1 cm sideways on its mount (the check flags 1 cm or 1 degree).
    if (active) f.bumped_from_s = t, f.bumped_until_s = never, f.bump_x_m = 0.01;
    else f.bumped_until_s = std::min(f.bumped_until_s, t);
  } else {
    return false;
  }
  d415_.set_faults(f);
  return true;
}

std::string EmulatedCameraRig::emulation_spec() const {
  return bridge_->emulation_spec(camera_.depth_device, camera_.color_device);
}

}  // namespace sim_hw
