// The replay camera's live=1 option (used by the cell benchmark): a late reader gets the newest
// frame already due, as from a live camera, and looped passes continue the sequence and device
// time so that the frame monitor sees one unbroken stream (without it the loop restarts both).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "drivers/replay_camera.h"
#include "drivers/session_recorder.h"
#include "sim_hw/simulated_d415.h"
#include "tests/sim_hw/d415_test_scenes.h"

namespace {

namespace fs = std::filesystem;
using drivers::ReadStatus;

// n frames of one simulated camera (simulated clock: 30 fps spacing, no drops) in a new session.
fs::path record_session(const std::string& name, int n) {
  const fs::path dir = fs::temp_directory_path() / ("replay_live_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  sim_hw::SimulatedD415Options o;
  auto scene = sim_hw_test::floor_only();
  o.scene = [scene](double) { return scene; };
  sim_hw::SimulatedD415Camera cam(o);
  auto c = sim_hw_test::config_848("cam", sim_hw_test::looking_down(1.4));
  c.color_mode = {0, 0, 0};
  REQUIRE(cam.configure(c).ok);
  REQUIRE(cam.activate().ok);
  drivers::SessionRecorder rec(dir);
  REQUIRE(drivers::record_frames(cam, rec, n, 2 * n) == static_cast<std::uint64_t>(n));
  return dir;
}

std::unique_ptr<drivers::ReplayDepthCamera> replay(const fs::path& dir, const std::string& options) {
  auto cam = std::make_unique<drivers::ReplayDepthCamera>();
  drivers::CameraConfig c;
  c.name = "cam";
  c.uri = dir.string() + "#cam?" + options;
  REQUIRE(cam->configure(c).ok);
  REQUIRE(cam->activate().ok);
  return cam;
}

}  // namespace

TEST_CASE("replay live=1: looped passes continue the sequence and the device clock", "[replay_live]") {
  const fs::path dir = record_session("loop", 4);
  auto cam = replay(dir, "pace=fast&loop=1&rebase=1&live=1");
  drivers::DepthFrame f;
  std::vector<std::uint64_t> seq;
  std::vector<std::int64_t> device;
  for (int i = 0; i < 10; ++i) {
    REQUIRE(cam->read(f) == ReadStatus::kFrame);
    seq.push_back(f.sequence);
    device.push_back(f.device_time_us);
  }
  const std::int64_t period_us = device[1] - device[0];
  CHECK(period_us > 30000);
  CHECK(period_us < 36000);
  for (int i = 1; i < 10; ++i) {
    CHECK(seq[i] == seq[i - 1] + 1);  // across the loops at i = 4 and 8 too
    CHECK(std::abs(device[i] - device[i - 1] - period_us) <= 1);
  }
  CHECK(cam->health().dropped == 0);

  // Without live=1 the loop restarts both, which a frame monitor rejects as stale.
  auto plain = replay(dir, "pace=fast&loop=1&rebase=1");
  for (int i = 0; i < 5; ++i) REQUIRE(plain->read(f) == ReadStatus::kFrame);
  CHECK(f.sequence == seq[0]);
  CHECK(f.device_time_us == device[0]);
  fs::remove_all(dir);
}

TEST_CASE("replay live=1: a late reader gets the newest due frame, the skipped ones count as dropped",
          "[replay_live]") {
  const fs::path dir = record_session("late", 12);
  for (const bool live : {false, true}) {
    auto cam = replay(dir, live ? "pace=recorded&live=1" : "pace=recorded");
    drivers::DepthFrame f;
    REQUIRE(cam->read(f) == ReadStatus::kFrame);
    const std::uint64_t first = f.sequence;
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // frames 1..4 fall due meanwhile
    REQUIRE(cam->read(f) == ReadStatus::kFrame);
    if (live) {
      CHECK(f.sequence >= first + 4);
      CHECK(cam->health().dropped == f.sequence - first - 1);
    } else {
      CHECK(f.sequence == first + 1);  // every frame in turn, however late
      CHECK(cam->health().dropped == 0);
    }
  }
  fs::remove_all(dir);
}
