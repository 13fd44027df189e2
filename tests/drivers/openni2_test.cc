// The "openni2" back-end against the OpenNI2 simulation plug-in, through OpenNI2 itself: each
// case builds a private OpenNI2 installation (openni2_test_env.h) and runs its hidden twin from
// openni2_child_test.cc in a child process. Plus the plug-in's config reader and the test-pattern
// camera, which need no OpenNI2.

#include <catch2/catch.hpp>

#include "sim_hw/openni2_sim_config.h"
#include "sim_hw/test_pattern_camera.h"
#include "tests/drivers/openni2_test_env.h"

namespace {

// The plug-in's devices for every child: all draw from the test_pattern camera.
const char* kSimCameras = R"([
  {"name": "cam", "backend": "test_pattern", "serial": "821312060001",
   "depth_mode": {"width": 424, "height": 240, "fps": 30},
   "color_mode": {"width": 424, "height": 240, "fps": 30}, "on_demand": true},
  {"name": "dying", "backend": "test_pattern", "uri": "dead_after=5",
   "depth_mode": {"width": 424, "height": 240, "fps": 30}, "on_demand": true, "replug_after_ms": 150},
  {"name": "gone", "backend": "test_pattern", "uri": "dead_after=3",
   "depth_mode": {"width": 424, "height": 240, "fps": 30}, "on_demand": true},
  {"name": "frozen", "backend": "test_pattern", "uri": "freeze_after=3",
   "depth_mode": {"width": 424, "height": 240, "fps": 30}, "on_demand": true},
  {"name": "stale", "backend": "test_pattern", "uri": "stale_after=3",
   "depth_mode": {"width": 424, "height": 240, "fps": 30}, "on_demand": true},
  {"name": "sim", "backend": "simulated", "uri": "@DIR@/scene.json", "serial": "821312060002",
   "depth_mode": {"width": 848, "height": 480, "fps": 30},
   "color_mode": {"width": 848, "height": 480, "fps": 30},
   "camera_to_cell": [1, 0, 0, 0,  0, -1, 0, 0,  0, 0, -1, 1.5,  0, 0, 0, 1], "on_demand": true},
  {"name": "sim_dying", "backend": "simulated", "uri": "@DIR@/scene_dead.json",
   "depth_mode": {"width": 848, "height": 480, "fps": 30},
   "color_mode": {"width": 848, "height": 480, "fps": 30},
   "camera_to_cell": [1, 0, 0, 0,  0, -1, 0, 0,  0, 0, -1, 1.5,  0, 0, 0, 1], "on_demand": true,
   "replug_after_ms": 100},
  {"name": "live", "backend": "test_pattern",
   "depth_mode": {"width": 424, "height": 240, "fps": 30},
   "color_mode": {"width": 424, "height": 240, "fps": 30}}
])";

// A dark sheet 1.0-1.1 m below a camera 1.5 m above the floor (the simulated D415's scene file).
const char* kScene = R"({
  "meshes": [{"name": "sheet", "albedo": [40, 40, 45],
              "vertices": [[-0.3, -0.2, 0.4], [0.3, -0.2, 0.45], [0.3, 0.2, 0.5], [-0.3, 0.2, 0.42]],
              "triangles": [[0, 1, 2], [0, 2, 3]]}],
  "floor": {"height_m": 0.0}, "seed": 7, "clock": "simulated" @FAULTS@
})";

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

std::string run_in_openni2(const std::string& child_case) {
  testing_support::OpenNI2TestEnv env;
  env.write_sim_config(replace_all(kSimCameras, "@DIR@", env.dir()));
  testing_support::write_file(env.path("scene.json"), replace_all(kScene, "@FAULTS@", ""));
  // The camera dies 0.15 s into its (simulated) time: after 4 frames at 30 fps.
  testing_support::write_file(env.path("scene_dead.json"),
                              replace_all(kScene, "@FAULTS@", R"(, "faults": {"dead_from_s": 0.15})"));
  const auto result = env.run_child(child_case);
  INFO("child output:\n" << result.output);
  CHECK(result.exit_code == 0);
  CHECK_THAT(result.output, Catch::Contains("All tests passed"));
  return result.output;
}

}  // namespace

TEST_CASE("openni2 back-end reads a plug-in device bit-exact", "[openni2]") {
  run_in_openni2("child openni2 reads plug-in frames");
}

TEST_CASE("openni2 back-end opens \"any\" and sets another D415 mode", "[openni2]") {
  run_in_openni2("child openni2 opens any device and switches the plug-in's mode");
}

TEST_CASE("openni2 mode negotiation failure lists the device's modes", "[openni2]") {
  run_in_openni2("child openni2 mode negotiation failure lists the modes");
}

TEST_CASE("openni2 serial mismatch is a clear error", "[openni2]") {
  run_in_openni2("child openni2 serial mismatch and unknown device are clear errors");
}

TEST_CASE("openni2 recording to .oni replays the same frames", "[openni2]") {
  run_in_openni2("child openni2 records to .oni and replays the same frames");
}

TEST_CASE("openni2 device removal is kLost and reopened", "[openni2]") {
  run_in_openni2("child openni2 device removal is kLost then reopened when it returns");
}

TEST_CASE("openni2 device that never returns stays kLost", "[openni2]") {
  run_in_openni2("child openni2 device that never returns stays kLost");
}

TEST_CASE("openni2 frozen and stale streams are flagged", "[openni2]") {
  run_in_openni2("child openni2 frozen and stale streams are flagged");
}

TEST_CASE("openni2 back-end reads a simulated D415 through the plug-in bit-exact", "[openni2]") {
  run_in_openni2("child openni2 simulated D415 through the plug-in");
}

TEST_CASE("openni2 simulated D415 going dead is kLost and comes back", "[openni2]") {
  run_in_openni2("child openni2 simulated D415 going dead");
}

TEST_CASE("openni2 free-running plug-in device", "[openni2]") {
  run_in_openni2("child openni2 free-running device pushes frames at its rate");
}

TEST_CASE("openni2 plug-in config errors name the file and field", "[openni2]") {
  testing_support::TempDir dir("openni2_sim_config");
  const auto path = dir / "cams.json";
  testing_support::write_file(path, R"([{"name": "a", "backend": "simulated",
      "depth_mode": {"width": 848, "height": 480, "fps": 30}, "on_demand": "yes"}])");
  CHECK_THROWS_WITH(sim_hw::read_openni2_sim_config(path.string()), Catch::Contains("cams.json") &&
                                                                        Catch::Contains("on_demand") &&
                                                                        Catch::Contains("true or false"));
  testing_support::write_file(path, R"([{"name": "a", "backend": "simulated",
      "depth_mode": {"width": 848, "height": 480, "fps": 30}, "fov": 65}])");
  CHECK_THROWS_WITH(sim_hw::read_openni2_sim_config(path.string()), Catch::Contains("fov"));
  testing_support::write_file(path,
                              R"([{"name": "a", "backend": "simulated", "depth_mode": {"width": 848}}])");
  CHECK_THROWS_WITH(sim_hw::read_openni2_sim_config(path.string()), Catch::Contains("depth_mode.height"));
  testing_support::write_file(path, R"([{"name": "a", "backend": "test_pattern",
      "depth_mode": {"width": 64, "height": 48, "fps": 30}, "replug_after_ms": 20,
      "camera_to_cell": [1,0,0,0.5, 0,1,0,0, 0,0,1,1.5, 0,0,0,1]}])");
  const auto devices = sim_hw::read_openni2_sim_config(path.string());
  REQUIRE(devices.size() == 1);
  CHECK(devices[0].replug_after_ms == 20);
  CHECK_FALSE(devices[0].has_color);
  CHECK(devices[0].source.camera_to_cell.translation().z() == 1.5);
}

TEST_CASE("test pattern camera is deterministic and dies on cue", "[openni2]") {
  sim_hw::TestPatternCamera camera;
  drivers::CameraConfig config;
  config.name = "p";
  config.depth_mode = {32, 24, 30};
  config.color_mode = {0, 0, 0};
  config.uri = "dead_after=2";
  REQUIRE(camera.configure(config).ok);
  REQUIRE(camera.activate().ok);
  drivers::DepthFrame a, b;
  REQUIRE(camera.read(a) == drivers::ReadStatus::kFrame);
  REQUIRE(camera.read(b) == drivers::ReadStatus::kFrame);
  CHECK(a.depth_mm != b.depth_mm);
  CHECK(b.depth_mm[5] == sim_hw::test_pattern_depth_mm(2, 5, 0, 32, 24));
  CHECK(std::count(a.depth_mm.begin(), a.depth_mm.end(), 0) > 0);  // has invalid pixels
  CHECK(camera.read(b) == drivers::ReadStatus::kLost);
  CHECK(camera.health().state == drivers::CameraState::kLost);
  config.uri = "dead_after=x";
  CHECK_FALSE(camera.configure(config).ok);
  config.uri = "dead_after=1,wobble=2";
  CHECK_THAT(camera.configure(config).message, Catch::Contains("\"wobble=2\""));
  config.uri = "freeze_after=1,stale_after=2";
  REQUIRE(camera.configure(config).ok);
  REQUIRE(camera.activate().ok);
  REQUIRE(camera.read(a) == drivers::ReadStatus::kFrame);
  REQUIRE(camera.read(b) == drivers::ReadStatus::kFrame);
  CHECK(a.depth_mm == b.depth_mm);  // frozen image, running clock
  CHECK(b.device_time_us > a.device_time_us);
  REQUIRE(camera.read(a) == drivers::ReadStatus::kFrame);
  CHECK(a.device_time_us == b.device_time_us);  // stale clock
  CHECK(a.sequence == 3);
}

// Debian's own test driver (libDummyDevice: URI "Dummy", 320x240 depth and RGB at 30 fps from its
// own threads, one mode) shows the back-end working with a driver we did not write.
TEST_CASE("openni2 back-end reads Debian's DummyDevice driver", "[openni2]") {
  testing_support::OpenNI2TestEnv env({"libDummyDevice.so.0"});
  env.write_sim_config("[]");
  const auto result = env.run_child("child openni2 reads the Dummy device");
  INFO("child output:\n" << result.output);
  CHECK(result.exit_code == 0);
  CHECK_THAT(result.output, Catch::Contains("All tests passed"));
}

TEST_CASE("openni2_record tool records a plug-in device and rejects bad input", "[openni2]") {
  testing_support::OpenNI2TestEnv env;
  env.write_sim_config(replace_all(kSimCameras, "@DIR@", env.dir()));
  const std::string oni = env.path("tool.oni").string();
  auto result = env.run({OPENNI2_RECORD_EXE, "--uri", "prepreg-sim://cam", "--out", oni, "--frames", "5",
                         "--depth", "424x240@30", "--color", "424x240@30", "--serial", "821312060001"});
  INFO(result.output);
  CHECK(result.exit_code == 0);
  CHECK_THAT(result.output, Catch::Contains("5 depth and 5 colour frames from prepreg-sim://cam"));
  CHECK(std::filesystem::file_size(oni) > 5u * 424 * 240);
  result = env.run({OPENNI2_RECORD_EXE, "--uri", "prepreg-sim://cam", "--out", oni, "--depth", "424x240"});
  CHECK(result.exit_code != 0);
  CHECK_THAT(result.output, Catch::Contains("--depth") && Catch::Contains("WIDTHxHEIGHT@FPS"));
  result = env.run({OPENNI2_RECORD_EXE, "--uri", "prepreg-sim://cam", "--out", oni, "--serial", "1"});
  CHECK(result.exit_code == 2);
  CHECK_THAT(result.output, Catch::Contains("is not serial \"1\""));
}

// By hand: ./openni2_tests "[.openni2-bench]" -s  (prints ms per read through OpenNI2 vs direct)
TEST_CASE("openni2 read cost through the plug-in", "[.openni2-bench]") {
  std::printf("%s", run_in_openni2("child openni2 read cost").c_str());
}
