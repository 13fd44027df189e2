#include <catch2/catch.hpp>

#include "drivers/monitored_depth_camera.h"
#include "tests/support/synthetic_depth_camera.h"

namespace {

using drivers::ReadStatus;

using testing_support::SyntheticTestCamera;

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
