// A camera served as an emulated V4L2 device (sim_hw::V4l2CameraBridge) and read back through
// the real V4L2 back-end and the frame monitor, in one process (EmulatedV4l2Io): frames and the
// source camera's faults arrive as the driver would see them from a device.

#include <unistd.h>

#include <catch2/catch.hpp>

#include "drivers/monitored_depth_camera.h"
#include "drivers/v4l2_d415_camera.h"
#include "sim_hw/emulated_v4l2_io.h"
#include "sim_hw/v4l2_camera_bridge.h"
#include "tests/support/synthetic_depth_camera.h"

namespace {

using drivers::ReadStatus;
using testing_support::SyntheticTestCamera;

struct BridgeRig {
  drivers::CameraConfig config;
  SyntheticTestCamera source;
  std::unique_ptr<sim_hw::V4l2CameraBridge> bridge;
  std::unique_ptr<drivers::MonitoredDepthCamera> reader;
  drivers::DepthFrame frame;

  BridgeRig() {
    config.name = "cam_bridge";
    config.depth_mode = config.color_mode = {32, 24, 30};
    config.depth_intrinsics = config.color_intrinsics = {32, 24, 30.0, 30.0, 16.0, 12.0};
    config.read_timeout = std::chrono::milliseconds(50);
    REQUIRE(source.configure(config).ok);
    REQUIRE(source.activate().ok);
    const std::string prefix = "prepreg_bridgetest_" + std::to_string(::getpid());
    bridge = std::make_unique<sim_hw::V4l2CameraBridge>(source, config, prefix);
    CHECK(bridge->emulation_spec("/dev/video0", "/dev/video2") ==
          "/dev/video0=" + prefix + "_depth,/dev/video2=" + prefix + "_color");
    drivers::CameraConfig v4l2 = config;
    v4l2.backend = "v4l2";
    v4l2.uri = bridge->v4l2_uri("/dev/video0", "/dev/video2");
    auto io = std::make_shared<sim_hw::EmulatedV4l2Io>(std::map<std::string, std::string>{
        {"/dev/video0", prefix + "_depth"}, {"/dev/video2", prefix + "_color"}});
    reader = std::make_unique<drivers::MonitoredDepthCamera>(std::make_unique<drivers::V4l2D415Camera>(io));
    REQUIRE(reader->configure(v4l2).ok);
    REQUIRE(reader->activate().ok);
  }
  ReadStatus step() {
    bridge->pump();
    return reader->read(frame);
  }
};

}  // namespace

TEST_CASE("bridge: frames of a camera arrive through the V4L2 back-end unchanged", "[v4l2_emulation]") {
  BridgeRig rig;
  drivers::DepthFrame direct;
  std::int64_t first_time_us = 0;
  for (int i = 0; i < 5; ++i) {
    REQUIRE(rig.step() == ReadStatus::kFrame);
    CHECK(rig.frame.sequence == static_cast<std::uint64_t>(i + 1));
    if (i == 0) first_time_us = rig.frame.device_time_us;
    CHECK(rig.frame.device_time_us - first_time_us == 33'333 * i);  // the camera's clock, rebased
    CHECK(rig.frame.rgb.size() == 32u * 24u * 3u);
  }
  // The same synthetic stream read directly: depth identical (a fresh source with the same seed).
  SyntheticTestCamera again;
  REQUIRE(again.configure(rig.config).ok);
  REQUIRE(again.activate().ok);
  for (int i = 0; i < 5; ++i) REQUIRE(again.read(direct) == ReadStatus::kFrame);
  CHECK(rig.frame.depth_mm == direct.depth_mm);
  int worst = 0;
  for (std::size_t j = 0; j < direct.rgb.size(); ++j) worst = std::max(worst, std::abs(rig.frame.rgb[j] - direct.rgb[j]));
  CHECK(worst <= 3);
}

TEST_CASE("bridge: the source's faults reach the V4L2 reader's monitor", "[v4l2_emulation]") {
  BridgeRig rig;
  for (int i = 0; i < 3; ++i) REQUIRE(rig.step() == ReadStatus::kFrame);

  rig.source.fault = SyntheticTestCamera::Fault::kFreeze;
  int frozen_at = 0;
  for (int i = 1; i <= 3 && frozen_at == 0; ++i)
    if (rig.step() == ReadStatus::kFrozen) frozen_at = i;
  CHECK(frozen_at >= 1);
  CHECK(frozen_at <= 3);

  rig.source.fault = SyntheticTestCamera::Fault::kClockStuck;
  CHECK(rig.step() == ReadStatus::kStale);

  rig.source.fault = SyntheticTestCamera::Fault::kDrop3;
  CHECK(rig.step() == ReadStatus::kFrame);
  CHECK(rig.reader->health().dropped == 3);

  rig.source.fault = SyntheticTestCamera::Fault::kAllZero;
  CHECK(rig.step() == ReadStatus::kCorrupt);
  rig.source.fault = SyntheticTestCamera::Fault::kWrongSize;  // goes out as a short buffer
  CHECK(rig.step() == ReadStatus::kCorrupt);
  CHECK_THAT(rig.reader->health().message, Catch::Contains("depth image has 736 pixels"));

  rig.source.fault = SyntheticTestCamera::Fault::kLost;  // dead camera: the nodes are unplugged
  CHECK(rig.step() == ReadStatus::kLost);
  CHECK(rig.reader->health().state == drivers::CameraState::kLost);
  rig.source.fault = SyntheticTestCamera::Fault::kNone;  // back: fresh nodes; reader reopens
  ReadStatus s = ReadStatus::kLost;
  for (int i = 0; i < 10 && s != ReadStatus::kFrame; ++i) s = rig.step();
  CHECK(s == ReadStatus::kFrame);
  CHECK(rig.reader->health().reopened == 1);
  CHECK(rig.reader->health().state == drivers::CameraState::kActive);
}
