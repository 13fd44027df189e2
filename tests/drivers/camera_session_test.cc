// Recording a camera session and replaying it: bit-exact round trip, the "replay" back-end via
// the registry, pacing, end of recording, and errors naming the bad file and field or line.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "drivers/camera_registry.h"
#include "drivers/pnm_image.h"
#include "drivers/replay_camera.h"
#include "drivers/session_recorder.h"
#include "sim_hw/simulated_d415.h"
#include "tests/sim_hw/d415_test_scenes.h"
#include "tests/support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using drivers::ReadStatus;


// A simulated camera looking down at a floor and a box (seeded, simulated clock).
std::unique_ptr<sim_hw::SimulatedD415Camera> sim_camera(const std::string& name, bool color = true) {
  sim_hw::SimulatedD415Options o;
  auto scene = sim_hw_test::floor_only();
  scene->meshes.push_back(sim_hw::make_box_mesh("box", {-0.2, -0.1, 0}, {0.1, 0.2, 0.3}, {40, 40, 45}));
  o.scene = [scene](double) { return scene; };
  o.faults.drop_every_nth = 4;  // sequence gaps must survive the round trip
  auto cam = std::make_unique<sim_hw::SimulatedD415Camera>(o);
  auto c = sim_hw_test::config_848(name, sim_hw_test::looking_down(1.4));
  if (!color) c.color_mode = {0, 0, 0};
  REQUIRE(cam->configure(c).ok);
  REQUIRE(cam->activate().ok);
  return cam;
}

// Records n frames of each camera; returns them as read.
std::vector<drivers::DepthFrame> record(const fs::path& dir, int n) {
  drivers::SessionRecorder rec(dir);
  auto a = sim_camera("cam_a"), b = sim_camera("cam_b", false);
  std::vector<drivers::DepthFrame> frames;
  for (int i = 0; i < n; ++i) {
    for (auto* cam : {a.get(), b.get()}) {
      drivers::DepthFrame f;
      REQUIRE(cam->read(f) == ReadStatus::kFrame);
      const auto r = rec.append(f);
      REQUIRE(r.ok);
      frames.push_back(f);
    }
  }
  CHECK(rec.frames("cam_a") == std::uint64_t(n));
  return frames;
}

void require_same(const drivers::DepthFrame& a, const drivers::DepthFrame& b) {
  REQUIRE(a.camera == b.camera);
  REQUIRE(a.sequence == b.sequence);
  REQUIRE(a.device_time_us == b.device_time_us);
  REQUIRE(a.host_time_us == b.host_time_us);
  for (const auto* k : {&a.depth_intrinsics, &a.color_intrinsics}) {
    const auto& l = k == &a.depth_intrinsics ? b.depth_intrinsics : b.color_intrinsics;
    REQUIRE((k->width == l.width && k->height == l.height && k->fx == l.fx && k->fy == l.fy &&
             k->cx == l.cx && k->cy == l.cy && k->k1 == l.k1 && k->k3 == l.k3));
  }
  REQUIRE(a.depth_to_color.matrix() == b.depth_to_color.matrix());
  REQUIRE(a.camera_to_cell.matrix() == b.camera_to_cell.matrix());
  REQUIRE(a.depth_mm == b.depth_mm);
  REQUIRE(a.rgb == b.rgb);
}

std::string configure_error(const std::string& uri) {
  drivers::ReplayDepthCamera cam;
  drivers::CameraConfig c;
  c.name = "r";
  c.uri = uri;
  const auto r = cam.configure(c);
  return r.ok ? "" : r.message;
}

}  // namespace

TEST_CASE("session: recording then replaying is bit-exact, through the registry", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_session_roundtrip");  // removed when the case ends
  const fs::path dir = tmp / "session";
  const auto recorded = record(dir, 5);
  CHECK(fs::exists(dir / "session.json"));
  CHECK(fs::exists(dir / "cam_a" / "index.txt"));
  CHECK(fs::exists(dir / "cam_a" / "color_000004.ppm"));
  CHECK_FALSE(fs::exists(dir / "cam_b" / "color_000000.ppm"));  // cam_b has no colour stream
  drivers::register_real_depth_cameras();
  for (const std::string name : {"cam_a", "cam_b"}) {
    auto cam = drivers::make_depth_camera("replay");
    drivers::CameraConfig c;  // empty name: keep the recorded one
    c.uri = dir.string() + "#" + name + "?pace=fast";
    const auto r = cam->configure(c);
    REQUIRE(r.ok);
    REQUIRE(cam->activate().ok);
    drivers::DepthFrame f;
    for (const auto& rec : recorded) {
      if (rec.camera != name) continue;
      REQUIRE(cam->read(f) == ReadStatus::kFrame);
      require_same(f, rec);
    }
    CHECK(cam->read(f) == ReadStatus::kTimeout);  // end of recording
    CHECK_THAT(cam->health().message, Catch::Contains("end of recording (5 frames)"));
    CHECK(cam->health().dropped == 1);  // frame 3 dropped by the simulated camera
  }
}

TEST_CASE("session: replay paces as recorded, loops, and rebases host time on request", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_session_paced");  // removed when the case ends
  const fs::path dir = tmp / "session";
  const auto recorded = record(dir, 4);  // cam_a: 0, 1, 2, 4 at 33 ms spacing -> 133 ms span
  drivers::ReplayDepthCamera cam;
  drivers::CameraConfig c;
  c.name = "renamed";
  c.uri = dir.string() + "#cam_a?loop=1&rebase=1";
  REQUIRE(cam.configure(c).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::int64_t> host;
  for (int i = 0; i < 4; ++i) {
    REQUIRE(cam.read(f) == ReadStatus::kFrame);
    host.push_back(f.host_time_us);
  }
  // Paced: the first pass's frames came no sooner than recorded (how much later depends on the
  // machine, so no upper bound).
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(elapsed >= 0.13);
  // The loop's first frame, rebased onto the live steady clock: stamped between the read's start
  // and its end.
  const std::int64_t before_us = drivers::host_clock_us();
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  const std::int64_t after_us = drivers::host_clock_us();
  host.push_back(f.host_time_us);
  CHECK(f.camera == "renamed");
  CHECK(f.sequence == 0);  // looped back to the first frame
  CHECK(host[3] - host[0] == recorded[6].host_time_us - recorded[0].host_time_us);
  CHECK(host[4] >= before_us);
  CHECK(host[4] <= after_us);
}

TEST_CASE("session: frame files are standard 16-bit PGM and PPM", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_session_pnm");  // removed when the case ends
  const fs::path dir = tmp / "session";
  fs::create_directories(dir);
  const std::vector<std::uint16_t> depth = {0, 1, 256, 65535, 1234, 4321};
  REQUIRE(drivers::write_pgm16(dir / "d.pgm", 3, 2, depth).empty());
  std::ifstream in(dir / "d.pgm", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  CHECK(bytes.substr(0, 13) == "P5\n3 2\n65535\n");
  CHECK(bytes.size() == 13 + 12);
  CHECK(std::uint8_t(bytes[13 + 4]) == 1);  // 256 big-endian: 0x01 0x00
  CHECK(drivers::read_pgm16(dir / "d.pgm", 3, 2) == depth);
  CHECK_THROWS_WITH(drivers::read_pgm16(dir / "d.pgm", 4, 2),
                    Catch::Contains("d.pgm: image is 3x2, expected 4x2"));
  CHECK_THROWS_WITH(drivers::read_ppm8(dir / "d.pgm", 3, 2), Catch::Contains("d.pgm: not a binary PPM"));
  std::ofstream(dir / "t.pgm", std::ios::binary) << "P5\n3 2\n65535\n\x01\x02";
  CHECK_THROWS_WITH(drivers::read_pgm16(dir / "t.pgm", 3, 2), Catch::Contains("t.pgm: truncated"));
}

TEST_CASE("session: bad recordings give errors naming the file and field or line", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_session_bad");  // removed when the case ends
  const fs::path dir = tmp / "session";
  record(dir, 3);
  CHECK_THAT(configure_error(dir.string()), Catch::Contains("uri must be '<session dir>#<camera name>"));
  CHECK_THAT(configure_error(dir.string() + "#nope"),
             Catch::Contains("no camera 'nope' (it has: cam_a, cam_b)"));
  CHECK_THAT(configure_error(dir.string() + "#cam_a?speed=2"),
             Catch::Contains("unknown uri option 'speed=2'"));
  CHECK_THAT(configure_error("/nonexistent/x#cam_a"), Catch::Contains("session.json: cannot open"));
  // A session is never overwritten.
  CHECK_THROWS_WITH(drivers::SessionRecorder(dir), Catch::Contains("already holds a recorded session"));

  // Index: a malformed line, and a missing frame file.
  const fs::path index = dir / "cam_a" / "index.txt";
  std::string text;
  {
    std::ifstream in(index);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(index) << text << "7 123 oops depth_x.pgm -\n";
  CHECK_THAT(configure_error(dir.string() + "#cam_a"),
             Catch::Contains("index.txt:5: expected 'sequence device_time_us"));
  // A last line torn by a crash (no newline, not a whole record) is skipped; one that reads as a
  // frame is not, even without its newline.
  std::ofstream(index) << text;
  const std::size_t recorded = drivers::read_session_index(index).size();
  std::ofstream(index) << text << "7 123 45";
  CHECK(drivers::read_session_index(index).size() == recorded);
  std::ofstream(index) << text << "9 1 2 depth_000099.pgm -";
  CHECK(drivers::read_session_index(index).size() == recorded + 1);
  std::ofstream(index) << text << "9 1 2 depth_000099.pgm -\n";
  CHECK_THAT(configure_error(dir.string() + "#cam_a"),
             Catch::Contains("missing file") && Catch::Contains("depth_000099.pgm"));
  std::ofstream(index) << text;

  // session.json: a field with the wrong type.
  std::string json;
  {
    std::ifstream in(dir / "session.json");
    json.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto pos = json.find("\"fx\"");  // the first: color_intrinsics (keys are sorted)
  REQUIRE(pos != std::string::npos);
  std::string broken = json;
  broken.replace(pos, 4, "\"fX\"");
  std::ofstream(dir / "session.json") << broken;
  CHECK_THAT(configure_error(dir.string() + "#cam_a"),
             Catch::Contains("session.json: field 'cameras[0].color_intrinsics.fx' is missing"));
  std::ofstream(dir / "session.json") << "{\"format\": 1e400}";  // beyond a double (fuzzing)
  CHECK_THAT(configure_error(dir.string() + "#cam_a"),
             Catch::Contains("session.json: not valid JSON"));
  std::ofstream(dir / "session.json") << json;

  // A corrupt frame file at read time: skipped, named in health, the next frame delivered.
  std::ofstream(dir / "cam_a" / "depth_000001.pgm") << "P5\n1 1\n65535\n\x01\x02";
  drivers::ReplayDepthCamera cam;
  drivers::CameraConfig c;
  c.uri = dir.string() + "#cam_a?pace=fast";
  REQUIRE(cam.configure(c).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  CHECK(f.sequence == 2);
  CHECK_THAT(cam.health().message, Catch::Contains("depth_000001.pgm: image is 1x1, expected 848x480"));
  CHECK(cam.health().state == drivers::CameraState::kDegraded);
}

TEST_CASE("session: a looping replay whose every frame is corrupt returns from read", "[camera_sim]") {
  // Found by fuzzing (tests/fuzz session): with loop=1 read() went round the recording for ever.
  const testing_support::TempDir tmp("camera_session_all_corrupt");
  const fs::path dir = tmp / "session";
  record(dir, 3);
  for (const auto& entry : fs::directory_iterator(dir / "cam_a")) {
    if (entry.path().extension() == ".pgm") std::ofstream(entry.path()) << "P5\n1 1\n65535\n\x01\x02";
  }
  drivers::ReplayDepthCamera cam;
  drivers::CameraConfig c;
  c.uri = dir.string() + "#cam_a?pace=fast&loop=1";
  REQUIRE(cam.configure(c).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  CHECK(cam.read(f) == ReadStatus::kCorrupt);
  CHECK_THAT(cam.health().message, Catch::Contains("every recorded frame is corrupt") &&
                                       Catch::Contains(".pgm: image is 1x1"));
  CHECK(cam.read(f) == ReadStatus::kCorrupt);  // and again, without hanging
}

TEST_CASE("session: the record_cameras tool re-records a replayed camera bit-exactly", "[camera_sim]") {
  const testing_support::TempDir tmp("camera_session_tool");
  const fs::path dir = tmp / "src", out = tmp / "out";
  const auto recorded = record(dir, 4);
  const std::string cmd =
      fmt::format("{} --out {} --frames 3 --camera cam_a=replay:'{}#cam_a?pace=fast' > {} 2>&1",
                  RECORD_CAMERAS_EXE, out.string(), dir.string(), (dir / "tool.log").string());
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream log(dir / "tool.log");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  CHECK_THAT(text, Catch::Contains("cam_a: 3 frames recorded"));
  drivers::ReplayDepthCamera cam;
  drivers::CameraConfig c;
  c.uri = out.string() + "#cam_a?pace=fast";
  REQUIRE(cam.configure(c).ok);
  REQUIRE(cam.activate().ok);
  CHECK(cam.recorded_frames() == 3);
  drivers::DepthFrame f;
  for (int i = 0; i < 3; ++i) {
    REQUIRE(cam.read(f) == ReadStatus::kFrame);
    require_same(f, recorded[2 * i]);  // cam_a frames are the even entries
  }
  // A bad camera spec is reported, not crashed on.
  const std::string bad = fmt::format("{} --out {} --camera nonsense > /dev/null 2>&1", RECORD_CAMERAS_EXE,
                                      (tmp / "bad").string());
  CHECK(std::system(bad.c_str()) != 0);
}
