#include "sim_hw/test_pattern_camera.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "drivers/camera_registry.h"

namespace sim_hw {
namespace {

constexpr double kD415HorizontalFovRad = 65.0 * M_PI / 180.0;

// Square-pixel intrinsics of a D415-like 65 deg horizontal field of view.
drivers::Intrinsics default_intrinsics(int width, int height) {
  drivers::Intrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.5 * width / std::tan(0.5 * kD415HorizontalFovRad);
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

drivers::Intrinsics intrinsics_for(const drivers::Intrinsics& configured, const drivers::StreamMode& mode) {
  if (configured.width == mode.width && configured.height == mode.height) return configured;
  return default_intrinsics(mode.width, mode.height);
}

}  // namespace

std::uint16_t test_pattern_depth_mm(std::uint64_t sequence, int x, int y, int width, int height) {
  // Invalid pixels move with the frame number so a stuck or shifted image is caught.
  if ((static_cast<std::uint64_t>(x) * 7 + static_cast<std::uint64_t>(y) * 13 + sequence) % 53 == 0) {
    return 0;
  }
  const std::uint64_t plane =
      1200 + (static_cast<std::uint64_t>(x) * 300) / width + (static_cast<std::uint64_t>(y) * 200) / height;
  return static_cast<std::uint16_t>(plane + (x + 7 * sequence) % 64 + (y + 3 * sequence) % 32);
}

void test_pattern_rgb(std::uint64_t sequence, int x, int y, std::uint8_t rgb[3]) {
  rgb[0] = static_cast<std::uint8_t>(x + sequence);
  rgb[1] = static_cast<std::uint8_t>(y + 2 * sequence);
  rgb[2] = static_cast<std::uint8_t>((x ^ y) + sequence);
}

drivers::DriverResult TestPatternCamera::configure(const drivers::CameraConfig& config) {
  const auto& d = config.depth_mode;
  if (d.width <= 0 || d.height <= 0 || d.fps <= 0) {
    return drivers::DriverResult::failure(config.name + ": depth_mode needs positive width, height, fps");
  }
  dead_after_ = freeze_after_ = stale_after_ = -1;
  std::size_t start = 0;
  while (start < config.uri.size()) {
    const std::size_t end = std::min(config.uri.find(',', start), config.uri.size());
    const std::string item = config.uri.substr(start, end - start);
    start = end + 1;
    const std::size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    std::int64_t* target = key == "dead_after"     ? &dead_after_
                           : key == "freeze_after" ? &freeze_after_
                           : key == "stale_after"  ? &stale_after_
                                                   : nullptr;
    std::size_t used = 0;
    try {
      if (target != nullptr && eq != std::string::npos) *target = std::stoll(item.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (target == nullptr || used == 0 || used != item.size() - eq - 1 || *target < 0) {
      return drivers::DriverResult::failure(config.name + ": test_pattern uri item \"" + item +
                                            "\" is not dead_after=N, freeze_after=N or stale_after=N");
    }
  }
  config_ = config;
  sequence_ = 0;
  health_ = {};
  health_.state = drivers::CameraState::kConfigured;
  return drivers::DriverResult::success();
}

drivers::DriverResult TestPatternCamera::activate() {
  if (health_.state == drivers::CameraState::kUnconfigured) {
    return drivers::DriverResult::failure("test_pattern: activate() before configure()");
  }
  health_.state = drivers::CameraState::kActive;
  return drivers::DriverResult::success();
}

drivers::DriverResult TestPatternCamera::deactivate() {
  if (health_.state != drivers::CameraState::kUnconfigured) health_.state = drivers::CameraState::kConfigured;
  return drivers::DriverResult::success();
}

drivers::ReadStatus TestPatternCamera::read(drivers::DepthFrame& frame) {
  if (health_.state == drivers::CameraState::kLost) return drivers::ReadStatus::kLost;
  if (health_.state != drivers::CameraState::kActive) return drivers::ReadStatus::kNotActive;
  if (dead_after_ >= 0 && sequence_ >= static_cast<std::uint64_t>(dead_after_)) {
    health_.state = drivers::CameraState::kLost;
    health_.message = "test pattern camera died after " + std::to_string(dead_after_) + " frames";
    return drivers::ReadStatus::kLost;
  }
  ++sequence_;
  const auto& d = config_.depth_mode;
  const auto& c = config_.color_mode;
  frame.camera = config_.name;
  frame.sequence = sequence_;
  // Faults: a frozen sensor repeats its image, a stale one its timestamp.
  const std::uint64_t image =
      freeze_after_ >= 0 ? std::min<std::uint64_t>(sequence_, freeze_after_) : sequence_;
  const std::uint64_t clock =
      stale_after_ >= 0 ? std::min<std::uint64_t>(sequence_, stale_after_) : sequence_;
  frame.device_time_us = static_cast<std::int64_t>(clock * 1000000 / d.fps);
  frame.host_time_us = drivers::host_clock_us();
  frame.depth_intrinsics = intrinsics_for(config_.depth_intrinsics, d);
  frame.depth_mm.resize(static_cast<std::size_t>(d.width) * d.height);
  for (int y = 0; y < d.height; ++y) {
    for (int x = 0; x < d.width; ++x) {
      frame.depth_mm[static_cast<std::size_t>(y) * d.width + x] =
          test_pattern_depth_mm(image, x, y, d.width, d.height);
    }
  }
  frame.rgb.clear();
  frame.color_intrinsics = {};
  if (c.width > 0 && c.height > 0) {
    frame.color_intrinsics = intrinsics_for(config_.color_intrinsics, c);
    frame.rgb.resize(static_cast<std::size_t>(c.width) * c.height * 3);
    for (int y = 0; y < c.height; ++y) {
      for (int x = 0; x < c.width; ++x) {
        test_pattern_rgb(image, x, y, &frame.rgb[(static_cast<std::size_t>(y) * c.width + x) * 3]);
      }
    }
  }
  frame.depth_to_color = config_.depth_to_color;
  frame.camera_to_cell = config_.camera_to_cell;
  ++health_.frames;
  health_.last_frame_host_time_us = frame.host_time_us;
  return drivers::ReadStatus::kFrame;
}

void register_test_pattern_camera() {
  drivers::register_depth_camera_backend("test_pattern",
                                         [] { return std::make_unique<TestPatternCamera>(); });
}

}  // namespace sim_hw
