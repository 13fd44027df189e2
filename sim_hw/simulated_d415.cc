#include "sim_hw/simulated_d415.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>

#include <fmt/format.h>

#include "sim_hw/d415_model.h"
#include "sim_hw/d415_scene_file.h"

namespace sim_hw {
namespace {

// A device clock starts when the camera powers up, not when the host starts streaming (us).
constexpr std::int64_t kDeviceEpochUs = 5'000'000;

std::string mode_list(const std::vector<drivers::StreamMode>& modes) {
  std::string s;
  for (const auto& m : modes) s += fmt::format("{}{}x{}@{}", s.empty() ? "" : ", ", m.width, m.height, m.fps);
  return s;
}

}  // namespace

SimulatedD415Camera::SimulatedD415Camera(SimulatedD415Options options) : options_(std::move(options)) {}

void SimulatedD415Camera::set_faults(const D415FaultConfig& faults) {
  const std::lock_guard<std::mutex> lock(faults_mutex_);
  options_.faults = faults;
}

D415FaultConfig SimulatedD415Camera::faults() const {
  const std::lock_guard<std::mutex> lock(faults_mutex_);
  return options_.faults;
}

drivers::DriverResult SimulatedD415Camera::configure(const drivers::CameraConfig& config) {
  using drivers::DriverResult;
  const std::string who = fmt::format("simulated camera '{}'", config.name);
  if (active_) return DriverResult::failure(who + ": configure() while active; deactivate first");
  const auto& dm = config.depth_mode;
  if (!is_d415_mode(dm, d415_depth_modes())) {
    return DriverResult::failure(fmt::format("{}: depth_mode {}x{}@{} is not a D415 mode; expected one of {}",
                                             who, dm.width, dm.height, dm.fps, mode_list(d415_depth_modes())));
  }
  const auto& cm = config.color_mode;
  if (cm.width != 0) {
    if (!is_d415_mode(cm, d415_color_modes())) {
      return DriverResult::failure(fmt::format("{}: color_mode {}x{}@{} is not a D415 mode; expected one of {}",
                                               who, cm.width, cm.height, cm.fps, mode_list(d415_color_modes())));
    }
    if (cm.fps != dm.fps) {
      return DriverResult::failure(who + ": color_mode.fps must equal depth_mode.fps (frames are synchronised)");
    }
  }
  if (!(config.depth_unit_mm > 0.0)) return DriverResult::failure(who + ": depth_unit_mm must be > 0");
  if (config.read_timeout.count() <= 0) return DriverResult::failure(who + ": read_timeout must be > 0");
  if (!config.camera_to_cell.matrix().allFinite() || !config.depth_to_color.matrix().allFinite()) {
    return DriverResult::failure(who + ": camera_to_cell and depth_to_color must be finite");
  }
  const auto& dk = config.depth_intrinsics;
  if (dk.width != 0 && (dk.width != dm.width || dk.height != dm.height)) {
    return DriverResult::failure(who + ": depth_intrinsics size does not match depth_mode");
  }
  const auto& ck = config.color_intrinsics;
  if (ck.width != 0 && (ck.width != cm.width || ck.height != cm.height)) {
    return DriverResult::failure(who + ": color_intrinsics size does not match color_mode");
  }
  if (!config.uri.empty()) {
    try {
      SimulatedD415Options loaded = load_d415_scene_file(config.uri);
      const std::lock_guard<std::mutex> lock(faults_mutex_);
      options_ = std::move(loaded);
    } catch (const std::exception& e) {
      return DriverResult::failure(who + ": " + e.what());
    }
  } else if (!options_.scene) {
    return DriverResult::failure(who + ": no scene; set uri to a scene JSON file");
  }
  depth_k_ = dk.width != 0 ? dk : d415_depth_intrinsics(dm);
  color_k_ = cm.width == 0 ? drivers::Intrinsics{} : ck.width != 0 ? ck : d415_color_intrinsics(cm);
  depth_to_color_ = config.depth_to_color.matrix() == Eigen::Matrix4d::Identity()
                        ? d415_depth_to_color()
                        : config.depth_to_color;
  config_ = config;
  configured_ = true;
  health_ = {};
  health_.state = drivers::CameraState::kConfigured;
  return DriverResult::success();
}

drivers::DriverResult SimulatedD415Camera::activate() {
  if (!configured_) return drivers::DriverResult::failure("simulated camera: activate() before configure()");
  noise_rng_.seed(options_.seed);
  fault_rng_.seed(options_.seed ^ 0x9E3779B97F4A7C15ULL);  // independent of the noise stream
  next_index_ = 0;
  have_last_ = lost_ = false;
  sim_time_s_ = 0.0;
  activated_at_ = std::chrono::steady_clock::now();
  host_epoch_us_ = drivers::host_clock_us();
  active_ = true;
  health_.state = drivers::CameraState::kActive;
  health_.message.clear();
  return drivers::DriverResult::success();
}

drivers::DriverResult SimulatedD415Camera::deactivate() {
  active_ = false;
  if (configured_) health_.state = drivers::CameraState::kConfigured;
  return drivers::DriverResult::success();
}

drivers::CameraHealth SimulatedD415Camera::health() const { return health_; }

double SimulatedD415Camera::now_s() const {
  if (options_.clock == SimClock::kSimulated) return sim_time_s_;
  if (options_.clock == SimClock::kProcess) return 1e-6 * static_cast<double>(drivers::host_clock_us() - host_epoch_us_);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - activated_at_).count();
}

void SimulatedD415Camera::wait_until(double t_s) {
  if (options_.clock == SimClock::kWall) {  // kProcess never waits: read() only asks for due frames
    std::this_thread::sleep_until(activated_at_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                      std::chrono::duration<double>(t_s)));
  }
  if (t_s > sim_time_s_) sim_time_s_ = t_s;
}

bool SimulatedD415Camera::dropped(const D415FaultConfig& f, std::uint64_t index, double t_s) {
  // Draw for every frame so that a drop window does not shift the random stream.
  const bool by_chance = f.drop_probability > 0.0 &&
                         std::uniform_real_distribution<double>(0.0, 1.0)(fault_rng_) < f.drop_probability;
  const bool by_count = f.drop_every_nth > 0 && index % f.drop_every_nth == std::uint64_t(f.drop_every_nth - 1);
  return in_window(t_s, f.drop_from_s, f.drop_until_s) && (by_chance || by_count);
}

drivers::ReadStatus SimulatedD415Camera::read(drivers::DepthFrame& frame) {
  using drivers::ReadStatus;
  if (!active_) return ReadStatus::kNotActive;
  const D415FaultConfig f = faults();  // a snapshot: set_faults() may run on another thread
  const double fps = config_.depth_mode.fps;
  const double t_now = now_s();
  const double deadline = t_now + config_.read_timeout.count() / 1000.0;
  std::uint64_t k = next_index_;
  if (options_.clock != SimClock::kSimulated) k = std::max(k, std::uint64_t(std::floor(std::max(0.0, t_now) * fps)));
  double t = 0.0;
  for (;; ++k) {
    t = k / fps;
    if (options_.clock == SimClock::kProcess && t > t_now + 1e-9) {
      // Not due yet, and this clock cannot be waited for here: nothing new this time.
      next_index_ = k;
      ++health_.timeouts;
      return ReadStatus::kTimeout;
    }
    if (t > deadline) {
      wait_until(deadline);
      next_index_ = k;
      ++health_.timeouts;
      if (!lost_) health_.state = drivers::CameraState::kDegraded;
      health_.message = "no frame within read_timeout";
      return ReadStatus::kTimeout;
    }
    wait_until(t);
    if (in_window(t, f.dead_from_s, f.dead_until_s)) {
      next_index_ = k + 1;
      if (lost_) ++health_.reopen_attempts;  // every later read tries to reopen the device
      lost_ = true;
      health_.state = drivers::CameraState::kLost;
      health_.message = "device lost (simulated dead camera)";
      return ReadStatus::kLost;
    }
    if (lost_) {
      ++health_.reopen_attempts;
      ++health_.reopened;
      lost_ = false;
    }
    if (!dropped(f, k, t)) break;
  }
  next_index_ = k + 1;

  const bool frozen = have_last_ && in_window(t, f.frozen_from_s, f.frozen_until_s);
  const bool stale = in_window(t, f.stale_from_s, f.stale_until_s);
  double content_t = t;
  std::int64_t device_us = kDeviceEpochUs + std::llround(t * 1e6);
  if (stale && f.stale_mode == StaleMode::kLagging) {
    content_t = std::max(0.0, t - f.stale_lag_s);
    device_us = kDeviceEpochUs + std::llround(content_t * 1e6);
  } else if (stale) {
    device_us = kDeviceEpochUs + std::llround(std::max(0.0, f.stale_from_s) * 1e6);
  }
  frame.camera = config_.name;
  frame.sequence = k;
  if (frozen && !f.frozen_sequence_advances) {
    frame.sequence = last_sequence_;
    device_us = last_device_time_us_;
  }
  frame.device_time_us = device_us;
  frame.host_time_us = options_.clock != SimClock::kWall ? host_epoch_us_ + std::llround(t * 1e6) : drivers::host_clock_us();
  frame.depth_intrinsics = depth_k_;
  frame.color_intrinsics = color_k_;
  frame.depth_to_color = depth_to_color_;
  frame.camera_to_cell = config_.camera_to_cell;
  try {
    if (frozen) {
      frame.depth_mm = last_depth_;
      frame.rgb = last_rgb_;
    } else {
      const bool bumped = in_window(t, f.bumped_from_s, f.bumped_until_s);
      const Eigen::Isometry3d pose =
          bumped ? config_.camera_to_cell * Eigen::Translation3d(f.bump_x_m, f.bump_y_m, f.bump_z_m)
                 : config_.camera_to_cell;
      render(content_t, pose, frame);
      last_depth_ = frame.depth_mm;
      last_rgb_ = frame.rgb;
    }
  } catch (const std::exception& e) {  // a failing scene source must not escape read()
    health_.state = drivers::CameraState::kDegraded;
    health_.message = std::string("scene source failed: ") + e.what();
    ++health_.timeouts;
    return ReadStatus::kTimeout;
  }
  if (have_last_ && frame.sequence > last_sequence_ + 1) health_.dropped += frame.sequence - last_sequence_ - 1;
  have_last_ = true;
  last_sequence_ = frame.sequence;
  last_device_time_us_ = frame.device_time_us;
  ++health_.frames;
  health_.last_frame_host_time_us = frame.host_time_us;
  health_.state = drivers::CameraState::kActive;
  health_.message.clear();
  return ReadStatus::kFrame;
}

void SimulatedD415Camera::render(double t_s, const Eigen::Isometry3d& camera_to_cell, drivers::DepthFrame& frame) {
  static const RenderScene kEmpty;
  const std::shared_ptr<const RenderScene> snapshot = options_.scene(t_s);
  const RenderScene& scene = snapshot ? *snapshot : kEmpty;
  const auto& noise = options_.noise;
  const Eigen::Isometry3d right_in_depth = Eigen::Isometry3d(Eigen::Translation3d(kD415BaselineM, 0, 0));
  render_view(scene, camera_to_cell, depth_k_, left_);
  if (noise.stereo_shadow) render_view(scene, camera_to_cell * right_in_depth, depth_k_, right_);
  make_depth_image(left_, noise.stereo_shadow ? &right_ : nullptr, depth_k_, right_in_depth, noise,
                   config_.depth_unit_mm, noise_rng_, frame.depth_mm);
  if (color_k_.width == 0) {
    frame.rgb.clear();
    return;
  }
  const Eigen::Isometry3d color_to_cell = camera_to_cell * depth_to_color_.inverse();
  render_view(scene, color_to_cell, color_k_, color_);
  const Eigen::Vector3d light = color_to_cell.linear().transpose() * scene.light_direction_cell;
  make_color_image(color_, scene, light, noise, noise_rng_, frame.rgb);
}

}  // namespace sim_hw
