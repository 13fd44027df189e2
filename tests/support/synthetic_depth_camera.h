#pragma once
// A small DepthCamera for tests only: a seeded, noisy tilted plane (mm) at 30 fps with a device
// clock, and faults on demand. Header-only; needs only drivers/.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "drivers/depth_camera.h"

namespace testing_support {

class SyntheticTestCamera : public drivers::DepthCamera {
 public:
  enum class Fault { kNone, kFreeze, kClockStuck, kLate, kDrop3, kWrongSize, kAllZero, kNanPose, kNanFx, kLost };
  Fault fault = Fault::kNone;

  drivers::DriverResult configure(const drivers::CameraConfig& c) override {
    config_ = c;
    return drivers::DriverResult::success();
  }
  drivers::DriverResult activate() override {
    active_ = true;
    return drivers::DriverResult::success();
  }
  drivers::DriverResult deactivate() override {
    active_ = false;
    return drivers::DriverResult::success();
  }
  drivers::CameraHealth health() const override {
    drivers::CameraHealth h;
    h.state = lost_ ? drivers::CameraState::kLost : drivers::CameraState::kActive;
    return h;
  }
  void restart_device() {  // a reopened device: counter and clock start again
    sequence_ = 0;
    device_us_ = 1'000'000;
    lost_ = false;
  }

  drivers::ReadStatus read(drivers::DepthFrame& f) override {
    if (!active_) return drivers::ReadStatus::kNotActive;
    if (fault == Fault::kLost) {
      lost_ = true;
      return drivers::ReadStatus::kLost;
    }
    const bool freeze = fault == Fault::kFreeze && have_last_;
    sequence_ += fault == Fault::kDrop3 ? 4 : 1;
    if (fault != Fault::kClockStuck) device_us_ += 33'333;
    f.camera = config_.name;
    f.sequence = sequence_;
    f.device_time_us = device_us_;
    f.host_time_us = device_us_ + 7'000'000'000 + 2'000 + (fault == Fault::kLate ? 600'000 : 0);
    f.depth_intrinsics = config_.depth_intrinsics;
    f.camera_to_cell = Eigen::Isometry3d::Identity();
    f.depth_to_color = Eigen::Isometry3d::Identity();
    if (freeze) {
      f.depth_mm = last_depth_;  // the pipeline re-sends its last image
    } else {
      const int w = config_.depth_intrinsics.width, h = config_.depth_intrinsics.height;
      f.depth_mm.resize(static_cast<std::size_t>(w) * h);
      std::normal_distribution<double> noise(0.0, 1.5);  // mm
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) f.depth_mm[y * w + x] = static_cast<std::uint16_t>(1200 + 2 * x + y + noise(rng_));
    }
    f.color_intrinsics = config_.color_intrinsics;  // colour only when calibrated in the config
    f.rgb.assign(static_cast<std::size_t>(f.color_intrinsics.width) * f.color_intrinsics.height * 3, 0);
    for (std::size_t p = 0; p < f.rgb.size() / 3; ++p)  // pixel pairs share a colour (YUYV-friendly)
      for (int c = 0; c < 3; ++c) f.rgb[3 * p + c] = static_cast<std::uint8_t>(30 + ((p / 2) * (c + 2) + sequence_) % 180);
    if (fault == Fault::kWrongSize) f.depth_mm.resize(f.depth_mm.size() - 10);
    if (fault == Fault::kAllZero) std::fill(f.depth_mm.begin(), f.depth_mm.end(), 0);
    if (fault == Fault::kNanPose) f.camera_to_cell.translation().x() = std::numeric_limits<double>::quiet_NaN();
    if (fault == Fault::kNanFx) f.depth_intrinsics.fx = std::numeric_limits<double>::quiet_NaN();
    last_depth_ = f.depth_mm;
    have_last_ = true;
    return drivers::ReadStatus::kFrame;
  }

 private:
  drivers::CameraConfig config_;
  bool active_ = false, lost_ = false, have_last_ = false;
  std::uint64_t sequence_ = 0;
  std::int64_t device_us_ = 1'000'000;
  std::vector<std::uint16_t> last_depth_;
  std::mt19937 rng_{42};
};

}  // namespace testing_support
