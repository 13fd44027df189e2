#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "drivers/monitored_depth_camera.h"

namespace {

using drivers::ReadStatus;

// A small camera for these tests only: a seeded, noisy tilted plane at 30 fps with a device
// clock, and faults on demand.
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

  ReadStatus read(drivers::DepthFrame& f) override {
    if (!active_) return ReadStatus::kNotActive;
    if (fault == Fault::kLost) {
      lost_ = true;
      return ReadStatus::kLost;
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
    if (fault == Fault::kWrongSize) f.depth_mm.resize(f.depth_mm.size() - 10);
    if (fault == Fault::kAllZero) std::fill(f.depth_mm.begin(), f.depth_mm.end(), 0);
    if (fault == Fault::kNanPose) f.camera_to_cell.translation().x() = std::numeric_limits<double>::quiet_NaN();
    if (fault == Fault::kNanFx) f.depth_intrinsics.fx = std::numeric_limits<double>::quiet_NaN();
    last_depth_ = f.depth_mm;
    have_last_ = true;
    return ReadStatus::kFrame;
  }

 private:
  drivers::CameraConfig config_;
  bool active_ = false, lost_ = false, have_last_ = false;
  std::uint64_t sequence_ = 0;
  std::int64_t device_us_ = 1'000'000;
  std::vector<std::uint16_t> last_depth_;
  std::mt19937 rng_{42};
};

struct Fixture {
  SyntheticTestCamera* sim = nullptr;
  std::unique_ptr<drivers::MonitoredDepthCamera> cam;
  drivers::DepthFrame frame;

  Fixture() {
    auto inner = std::make_unique<SyntheticTestCamera>();
    sim = inner.get();
    cam = std::make_unique<drivers::MonitoredDepthCamera>(std::move(inner));
    drivers::CameraConfig c;  // default frozen_after_frames and stale_after
    c.name = "cam_test";
    c.depth_intrinsics = {32, 24, 30.0, 30.0, 16.0, 12.0};
    REQUIRE(cam->configure(c).ok);
    REQUIRE(cam->activate().ok);
  }
  ReadStatus read() { return cam->read(frame); }
  void good_frames(int n) {
    for (int i = 0; i < n; ++i) REQUIRE(read() == ReadStatus::kFrame);
  }
};

}  // namespace

TEST_CASE("monitor passes a healthy stream", "[monitor]") {
  Fixture f;
  f.good_frames(20);
  const drivers::CameraHealth h = f.cam->health();
  CHECK(h.state == drivers::CameraState::kActive);
  CHECK(h.frames == 20);
  CHECK(h.dropped == 0);
  CHECK(h.stale == 0);
  CHECK(h.frozen == 0);
  CHECK(h.message.empty());
}

TEST_CASE("monitor detects a frozen stream within 3 frames at default settings", "[monitor]") {
  Fixture f;
  f.good_frames(5);
  f.sim->fault = SyntheticTestCamera::Fault::kFreeze;
  int detected_at = 0;
  for (int i = 1; i <= 3 && detected_at == 0; ++i)
    if (f.read() == ReadStatus::kFrozen) detected_at = i;
  CHECK(detected_at >= 1);
  CHECK(detected_at <= 3);
  CHECK(f.read() == ReadStatus::kFrozen);  // stays flagged while frozen
  drivers::CameraHealth h = f.cam->health();
  CHECK(h.state == drivers::CameraState::kDegraded);
  CHECK_THAT(h.message, Catch::Contains("frozen"));
  CHECK(h.frozen >= 2);
  f.sim->fault = SyntheticTestCamera::Fault::kNone;
  CHECK(f.read() == ReadStatus::kFrame);
  CHECK(f.cam->health().state == drivers::CameraState::kActive);
}

TEST_CASE("monitor flags stale timestamps at once", "[monitor]") {
  Fixture f;
  f.good_frames(5);
  f.sim->fault = SyntheticTestCamera::Fault::kClockStuck;
  CHECK(f.read() == ReadStatus::kStale);
  CHECK_THAT(f.cam->health().message, Catch::Contains("device timestamp did not advance"));
  f.sim->fault = SyntheticTestCamera::Fault::kNone;
  CHECK(f.read() == ReadStatus::kFrame);
  f.sim->fault = SyntheticTestCamera::Fault::kLate;  // 600 ms in transit > stale_after 500 ms
  CHECK(f.read() == ReadStatus::kStale);
  const drivers::CameraHealth h = f.cam->health();
  CHECK(h.state == drivers::CameraState::kDegraded);
  CHECK_THAT(h.message, Catch::Contains("ms later than the device clock says (stale_after 500 ms)"));
  CHECK(h.stale == 2);
  f.sim->fault = SyntheticTestCamera::Fault::kNone;
  CHECK(f.read() == ReadStatus::kFrame);
}

TEST_CASE("monitor counts dropped frames from sequence gaps", "[monitor]") {
  Fixture f;
  f.good_frames(3);
  f.sim->fault = SyntheticTestCamera::Fault::kDrop3;
  CHECK(f.read() == ReadStatus::kFrame);  // a gap is counted, the frame itself is fine
  CHECK(f.read() == ReadStatus::kFrame);
  CHECK(f.cam->health().dropped == 6);
}

TEST_CASE("monitor rejects corrupt frames with a clear status", "[monitor]") {
  using Fault = SyntheticTestCamera::Fault;
  const std::pair<Fault, const char*> cases[] = {
      {Fault::kWrongSize, "depth image has 758 pixels, intrinsics say 32x24 = 768"},
      {Fault::kAllZero, "all zero"},
      {Fault::kNanPose, "camera_to_cell extrinsic is not finite"},
      {Fault::kNanFx, "depth intrinsics are not finite"},
  };
  Fixture f;
  f.good_frames(2);
  std::uint64_t corrupt = 0;
  for (const auto& [fault, text] : cases) {
    f.sim->fault = fault;
    CHECK(f.read() == ReadStatus::kCorrupt);
    CHECK(f.cam->corrupt_frames() == ++corrupt);
    CHECK(f.cam->health().state == drivers::CameraState::kDegraded);
    CHECK_THAT(f.cam->health().message, Catch::Contains(text));
    f.sim->fault = Fault::kNone;
    CHECK(f.read() == ReadStatus::kFrame);
  }
  CHECK(f.cam->health().frames == 2 + 4);  // corrupt frames are not delivered
}

TEST_CASE("monitor passes a loss through and restarts its baselines after it", "[monitor]") {
  Fixture f;
  f.good_frames(10);
  f.sim->fault = SyntheticTestCamera::Fault::kLost;
  CHECK(f.read() == ReadStatus::kLost);
  CHECK(f.cam->health().state == drivers::CameraState::kLost);
  f.sim->fault = SyntheticTestCamera::Fault::kNone;
  f.sim->restart_device();  // sequence and clock start again: neither a drop nor stale
  f.good_frames(3);
  CHECK(f.cam->health().dropped == 0);
  CHECK(f.cam->health().state == drivers::CameraState::kActive);
}
