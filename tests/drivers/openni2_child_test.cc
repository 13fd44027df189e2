// The OpenNI2 halves of the openni2 tests: hidden cases run by openni2_test.cc in a child process
// whose OpenNI2 loads only our simulation plug-in and OniFile (see openni2_test_env.h). The
// plug-in's devices come from kSimCameras in openni2_test.cc; their source is the test_pattern
// camera, so every pixel that arrives through OpenNI2 can be checked against the pattern.

#include <catch2/catch.hpp>

#include <ctime>
#include <thread>

#include "drivers/camera_registry.h"
#include "drivers/monitored_depth_camera.h"
#include "drivers/openni2_recorder.h"
#include "sim_hw/simulated_cameras.h"
#include "sim_hw/test_pattern_camera.h"
#include "tests/drivers/openni2_test_env.h"

namespace {

using drivers::ReadStatus;

drivers::CameraConfig openni2_config(const std::string& uri) {
  drivers::CameraConfig c;
  c.name = "cam_under_test";
  c.backend = "openni2";
  c.uri = uri;
  c.depth_mode = {424, 240, 30};
  c.color_mode = {424, 240, 30};
  c.read_timeout = std::chrono::milliseconds(200);
  return c;
}

std::unique_ptr<drivers::DepthCamera> openni2_camera() {
  drivers::register_real_depth_cameras();
  return drivers::make_depth_camera("openni2");
}

// The OpenNI2 back-end as the cell opens it: behind the generic frame monitor, which judges
// dropped, stale and frozen frames for every back-end.
std::unique_ptr<drivers::DepthCamera> monitored_openni2_camera() {
  drivers::register_real_depth_cameras();
  return drivers::make_monitored_depth_camera("openni2");
}

// The frame is the test pattern's frame `sequence`, pixel for pixel (depth and, if any, colour).
void require_pattern(const drivers::DepthFrame& frame, std::uint64_t sequence, bool with_color) {
  const int w = frame.depth_intrinsics.width, h = frame.depth_intrinsics.height;
  REQUIRE(frame.depth_mm.size() == static_cast<std::size_t>(w) * h);
  std::size_t wrong = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      wrong += frame.depth_mm[static_cast<std::size_t>(y) * w + x] !=
               sim_hw::test_pattern_depth_mm(sequence, x, y, w, h);
    }
  }
  INFO("frame " << sequence << ", first pixels " << frame.depth_mm[0] << " " << frame.depth_mm[1]
                << " expected " << sim_hw::test_pattern_depth_mm(sequence, 0, 0, w, h) << " "
                << sim_hw::test_pattern_depth_mm(sequence, 1, 0, w, h));
  REQUIRE(wrong == 0);
  if (!with_color) return;
  const int cw = frame.color_intrinsics.width, ch = frame.color_intrinsics.height;
  REQUIRE(frame.rgb.size() == static_cast<std::size_t>(cw) * ch * 3);
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      std::uint8_t expected[3];
      sim_hw::test_pattern_rgb(sequence, x, y, expected);
      const std::uint8_t* got = &frame.rgb[(static_cast<std::size_t>(y) * cw + x) * 3];
      wrong += got[0] != expected[0] || got[1] != expected[1] || got[2] != expected[2];
    }
  }
  REQUIRE(wrong == 0);
}

}  // namespace

TEST_CASE("child openni2 reads plug-in frames", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://cam");
  config.serial = "821312060001";
  const auto configured = camera->configure(config);
  INFO(configured.message);
  REQUIRE(configured.ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  for (std::uint64_t i = 1; i <= 8; ++i) {
    REQUIRE(camera->read(frame) == ReadStatus::kFrame);
    CHECK(frame.sequence == i);  // on-demand device: one source frame per read, none dropped
    CHECK(frame.device_time_us == static_cast<std::int64_t>(i * 1000000 / 30));
    CHECK(frame.camera == "cam_under_test");
    require_pattern(frame, frame.sequence, true);
  }
  // No calibration in the config: intrinsics come from the FOV the plug-in reports (65 deg).
  CHECK(frame.depth_intrinsics.width == 424);
  CHECK(frame.depth_intrinsics.fx == Approx(0.5 * 424 / std::tan(0.5 * 65.0 * M_PI / 180.0)).epsilon(1e-4));
  const drivers::CameraHealth health = camera->health();
  CHECK(health.frames == 8);
  CHECK(health.state == drivers::CameraState::kActive);
  REQUIRE(camera->deactivate().ok);
  CHECK(camera->read(frame) == ReadStatus::kNotActive);
}

TEST_CASE("child openni2 opens any device and switches the plug-in's mode", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("any");
  config.depth_mode = {848, 480, 30};  // a D415 mode the device offers but is not in
  const auto configured = camera->configure(config);
  INFO(configured.message);
  REQUIRE(configured.ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  REQUIRE(camera->read(frame) == ReadStatus::kFrame);
  CHECK(frame.depth_intrinsics.width == 848);
  CHECK(frame.color_intrinsics.width == 424);
  require_pattern(frame, frame.sequence, true);
}

TEST_CASE("child openni2 mode negotiation failure lists the modes", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://cam");
  config.depth_mode = {800, 600, 30};
  const auto result = camera->configure(config);
  REQUIRE_FALSE(result.ok);
  CHECK_THAT(result.message, Catch::Contains("cam_under_test") && Catch::Contains("800x600@30fps") &&
                                 Catch::Contains("424x240@30fps depth 1 mm") &&
                                 Catch::Contains("1280x720@30fps depth 1 mm") &&
                                 Catch::Contains("848x480@60fps depth 1 mm"));
  CHECK(camera->health().state == drivers::CameraState::kUnconfigured);
}

TEST_CASE("child openni2 serial mismatch and unknown device are clear errors", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://cam");
  config.serial = "999";
  auto result = camera->configure(config);
  REQUIRE_FALSE(result.ok);
  CHECK_THAT(result.message, Catch::Contains("serial number mismatch") &&
                                 Catch::Contains("\"821312060001\"") && Catch::Contains("\"999\""));
  config = openni2_config("prepreg-sim://nope");
  result = camera->configure(config);
  REQUIRE_FALSE(result.ok);
  CHECK_THAT(result.message, Catch::Contains("cannot open OpenNI2 device \"prepreg-sim://nope\""));
}

TEST_CASE("child openni2 records to .oni and replays the same frames", "[.openni2-child]") {
  const std::string oni = testing_support::openni2_test_dir() + "/session.oni";
  drivers::OpenNI2RecordingStats stats;
  const auto recorded = drivers::record_openni2_session(openni2_config("prepreg-sim://cam"), oni, 12, &stats);
  INFO(recorded.message);
  REQUIRE(recorded.ok);
  CHECK(stats.depth_frames == 12);

  auto camera = openni2_camera();
  const auto configured = camera->configure(openni2_config(oni));
  INFO(configured.message);
  REQUIRE(configured.ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  std::uint64_t replayed = 0;
  while (camera->read(frame) == ReadStatus::kFrame) {
    ++replayed;
    CHECK(frame.sequence == replayed);
    // The device made frames on demand, so recorded frame k is the source's frame k.
    require_pattern(frame, replayed, true);
  }
  CHECK(replayed == 12);
  CHECK(camera->read(frame) == ReadStatus::kTimeout);
  CHECK_THAT(camera->health().message, Catch::StartsWith("end of recording"));
}

TEST_CASE("child openni2 device removal is kLost then reopened when it returns", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://dying");  // source dies after 5
  config.read_timeout = std::chrono::milliseconds(50);
  REQUIRE(camera->configure(config).ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  for (int i = 0; i < 5; ++i) REQUIRE(camera->read(frame) == ReadStatus::kFrame);
  REQUIRE(camera->read(frame) == ReadStatus::kLost);
  CHECK(camera->health().state == drivers::CameraState::kLost);
  CHECK_THAT(camera->health().message, Catch::Contains("disconnected"));
  // The plug-in announces the device again 150 ms later (on its own thread, which a busy machine
  // may run late); reads keep trying to reopen. 30 s only keeps a device that never comes back
  // from hanging the test.
  ReadStatus status = ReadStatus::kLost;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (status != ReadStatus::kFrame && std::chrono::steady_clock::now() < give_up) {
    status = camera->read(frame);
    if (status != ReadStatus::kFrame) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  REQUIRE(status == ReadStatus::kFrame);
  CHECK(frame.sequence == 1);  // a fresh source after the replug
  require_pattern(frame, 1, false);
  const auto health = camera->health();
  CHECK(health.reopened == 1);
  CHECK(health.reopen_attempts >= 2);  // at least one failed while the device was away
  CHECK(health.state == drivers::CameraState::kActive);
}

TEST_CASE("child openni2 device that never returns stays kLost", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://gone");  // dies after 3, no replug
  config.read_timeout = std::chrono::milliseconds(20);
  REQUIRE(camera->configure(config).ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  for (int i = 0; i < 3; ++i) REQUIRE(camera->read(frame) == ReadStatus::kFrame);
  for (int i = 0; i < 10; ++i) {
    REQUIRE(camera->read(frame) == ReadStatus::kLost);
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  const auto health = camera->health();
  CHECK(health.reopen_attempts >= 3);
  CHECK(health.reopened == 0);
  CHECK_THAT(health.message, Catch::Contains("reopen failed") && Catch::Contains("prepreg-sim://gone"));
}

TEST_CASE("child openni2 frozen and stale streams are flagged", "[.openni2-child]") {
  drivers::CameraConfig config = openni2_config("prepreg-sim://frozen");  // image stops at frame 3
  config.frozen_after_frames = 3;
  drivers::DepthFrame frame;
  {
    // The bare back-end reports only what the driver knows: every frozen frame is a frame.
    auto bare = openni2_camera();
    REQUIRE(bare->configure(config).ok);
    REQUIRE(bare->activate().ok);
    for (int i = 0; i < 5; ++i) REQUIRE(bare->read(frame) == ReadStatus::kFrame);
    CHECK(bare->health().frozen == 0);
    CHECK(bare->health().frames == 5);
  }
  auto camera = monitored_openni2_camera();
  REQUIRE(camera->configure(config).ok);
  REQUIRE(camera->activate().ok);
  for (int i = 0; i < 4; ++i) REQUIRE(camera->read(frame) == ReadStatus::kFrame);
  // Frames 3, 4 and 5 are the same image: the third identical one is flagged.
  REQUIRE(camera->read(frame) == ReadStatus::kFrozen);
  CHECK(frame.sequence == 5);
  require_pattern(frame, 3, false);
  CHECK(camera->health().frozen == 1);
  CHECK(camera->health().state == drivers::CameraState::kDegraded);
  CHECK_THAT(camera->health().message, Catch::Contains("frozen"));

  camera = monitored_openni2_camera();
  REQUIRE(camera->configure(openni2_config("prepreg-sim://stale")).ok);  // clock stops at frame 3
  REQUIRE(camera->activate().ok);
  for (int i = 0; i < 3; ++i) REQUIRE(camera->read(frame) == ReadStatus::kFrame);
  REQUIRE(camera->read(frame) == ReadStatus::kStale);
  CHECK(frame.sequence == 4);
  require_pattern(frame, 4, false);  // a stale frame is still returned
  CHECK(camera->health().stale == 1);
  CHECK(camera->health().dropped == 0);
  CHECK(camera->health().state == drivers::CameraState::kDegraded);
  CHECK_THAT(camera->health().message, Catch::Contains("did not advance"));
}

// The plug-in's "sim" device and a "simulated" camera made here with the same config and scene
// (deterministic for the scene's seed) must give the same frames: OpenNI2 carries them unchanged.
TEST_CASE("child openni2 simulated D415 through the plug-in", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://sim");
  config.depth_mode = config.color_mode = {848, 480, 30};
  config.serial = "821312060002";
  const auto configured = camera->configure(config);
  INFO(configured.message);
  REQUIRE(configured.ok);
  REQUIRE(camera->activate().ok);

  sim_hw::register_simulated_depth_cameras();
  auto reference = drivers::make_depth_camera("simulated");
  drivers::CameraConfig direct = openni2_config(testing_support::openni2_test_dir() + "/scene.json");
  direct.name = "sim";
  direct.backend = "simulated";
  direct.depth_mode = direct.color_mode = {848, 480, 30};
  direct.camera_to_cell.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  direct.camera_to_cell.translation() = Eigen::Vector3d(0, 0, 1.5);
  REQUIRE(reference->configure(direct).ok);
  REQUIRE(reference->activate().ok);

  drivers::DepthFrame got, expected;
  for (int i = 0; i < 4; ++i) {
    REQUIRE(camera->read(got) == ReadStatus::kFrame);
    REQUIRE(reference->read(expected) == ReadStatus::kFrame);
    CHECK(got.sequence == expected.sequence);
    CHECK(got.device_time_us == expected.device_time_us);
    REQUIRE(got.depth_mm.size() == expected.depth_mm.size());
    CHECK(got.depth_mm == expected.depth_mm);
    CHECK(got.rgb == expected.rgb);
    // OpenNI2 carries the field of view, so the focal length arrives (to float precision).
    CHECK(got.depth_intrinsics.fx == Approx(expected.depth_intrinsics.fx).epsilon(1e-4));
    CHECK(got.color_intrinsics.fy == Approx(expected.color_intrinsics.fy).epsilon(1e-4));
  }
  // The sheet (1.0-1.1 m away) is in the image, not just the floor (1.5 m).
  const std::size_t centre = got.depth_mm.size() / 2 + got.depth_intrinsics.width / 2;
  CHECK(got.depth_mm[centre] > 950);
  CHECK(got.depth_mm[centre] < 1150);
}

TEST_CASE("child openni2 simulated D415 going dead", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://sim_dying");
  config.depth_mode = config.color_mode = {848, 480, 30};
  config.read_timeout = std::chrono::milliseconds(50);
  const auto configured = camera->configure(config);
  INFO(configured.message);
  REQUIRE(configured.ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  int frames = 0;
  ReadStatus status = ReadStatus::kFrame;
  while (frames < 20 && (status = camera->read(frame)) == ReadStatus::kFrame) ++frames;
  REQUIRE(status == ReadStatus::kLost);  // dead from 0.15 s of simulated time, at 30 fps
  CHECK(frames >= 4);
  CHECK(frames <= 6);
  CHECK(camera->health().state == drivers::CameraState::kLost);
  // Replugged after 150 ms, as above; 30 s only keeps a device that never returns from hanging.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (status != ReadStatus::kFrame && std::chrono::steady_clock::now() < give_up) {
    status = camera->read(frame);
    if (status != ReadStatus::kFrame) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  CHECK(status == ReadStatus::kFrame);  // replugged: a fresh simulated camera
  CHECK(camera->health().reopened == 1);
}

TEST_CASE("child openni2 free-running device pushes frames at its rate", "[.openni2-child]") {
  auto camera = openni2_camera();
  REQUIRE(camera->configure(openni2_config("prepreg-sim://live")).ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  std::uint64_t last = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 6; ++i) {
    REQUIRE(camera->read(frame) == ReadStatus::kFrame);
    CHECK(frame.sequence > last);
    last = frame.sequence;
    require_pattern(frame, frame.sequence, true);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(seconds > 4.0 / 30);  // paced at 30 fps, not as fast as possible
}

TEST_CASE("child openni2 reads the Dummy device", "[.openni2-child]") {
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("Dummy");
  config.depth_mode = {640, 480, 30};
  auto result = camera->configure(config);
  REQUIRE_FALSE(result.ok);
  CHECK_THAT(result.message, Catch::Contains("the device offers: 320x240@30fps depth 1 mm"));
  config.depth_mode = config.color_mode = {320, 240, 30};
  result = camera->configure(config);
  INFO(result.message);
  REQUIRE(result.ok);
  REQUIRE(camera->activate().ok);
  drivers::DepthFrame frame;
  std::uint64_t last = 0;
  for (int i = 0; i < 5; ++i) {
    REQUIRE(camera->read(frame) == ReadStatus::kFrame);
    CHECK(frame.sequence > last);
    last = frame.sequence;
    CHECK(frame.depth_mm[5] == 2000);  // the driver draws its first row at 2 m
    // Its colour thread starts a frame period after the depth one, so the first depth frames may
    // have no colour yet; later ones have.
    if (i >= 2) CHECK(frame.rgb.size() == 320u * 240 * 3);
    CHECK(frame.rgb.size() == static_cast<std::size_t>(frame.color_intrinsics.width) * 240 * 3);
  }
}

// Not a test: how long a read through OpenNI2 and the plug-in takes compared with reading the same
// source directly (848x480 depth + colour, on demand). Run by hand (see openni2_test.cc).
TEST_CASE("child openni2 read cost", "[.openni2-child]") {
  constexpr int kFrames = 120;
  auto camera = openni2_camera();
  drivers::CameraConfig config = openni2_config("prepreg-sim://sim");
  config.depth_mode = config.color_mode = {848, 480, 30};
  REQUIRE(camera->configure(config).ok);
  REQUIRE(camera->activate().ok);
  sim_hw::register_simulated_depth_cameras();
  auto direct = drivers::make_depth_camera("simulated");
  drivers::CameraConfig direct_config = config;
  direct_config.backend = "simulated";
  direct_config.uri = testing_support::openni2_test_dir() + "/scene.json";
  direct_config.camera_to_cell.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  direct_config.camera_to_cell.translation() = Eigen::Vector3d(0, 0, 1.5);
  REQUIRE(direct->configure(direct_config).ok);
  REQUIRE(direct->activate().ok);
  drivers::DepthFrame frame;
  const auto time_reads = [&](drivers::DepthCamera& cam) {
    // CPU time: this machine's cores are shared, and on demand all the work is in this thread.
    const std::clock_t start = std::clock();
    for (int i = 0; i < kFrames; ++i) REQUIRE(cam.read(frame) == ReadStatus::kFrame);
    return 1000.0 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC / kFrames;
  };
  const double via_openni2 = time_reads(*camera);
  const double direct_ms = time_reads(*direct);
  std::printf("848x480 depth+colour, simulated D415: %.2f ms CPU/read through OpenNI2, %.2f ms direct\n",
              via_openni2, direct_ms);
  // The same with the cheap test pattern as the source, so the OpenNI2 path's own cost shows.
  auto pattern_via = openni2_camera();
  drivers::CameraConfig pattern_config = openni2_config("prepreg-sim://cam");
  pattern_config.depth_mode = pattern_config.color_mode = {848, 480, 30};
  REQUIRE(pattern_via->configure(pattern_config).ok);
  REQUIRE(pattern_via->activate().ok);
  sim_hw::TestPatternCamera pattern_direct;
  pattern_config.uri.clear();
  REQUIRE(pattern_direct.configure(pattern_config).ok);
  REQUIRE(pattern_direct.activate().ok);
  const double pattern_via_ms = time_reads(*pattern_via);
  const double pattern_direct_ms = time_reads(pattern_direct);
  std::printf("848x480 depth+colour, test pattern: %.2f ms CPU/read through OpenNI2, %.2f ms direct\n",
              pattern_via_ms, pattern_direct_ms);
}
