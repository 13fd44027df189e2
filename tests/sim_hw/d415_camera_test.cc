// SimulatedD415Camera through the DepthCamera interface: lifecycle, frame contents, determinism
// by seed, each fault, and the wall clock.
#include <catch2/catch.hpp>

#include <chrono>

#include "sim_hw/d415_model.h"
#include "sim_hw/sheet_scene.h"
#include "sim_hw/simulated_d415.h"
#include "tests/sim_hw/d415_test_scenes.h"

namespace {

using drivers::ReadStatus;

// A floor 1.2 m below the camera, and a dark square whose height follows the simulation time
// (rising 0.1 m/s), so that frame content depends on the time it was rendered for.
sim_hw::SceneSource moving_scene() {
  return [](double t) {
    auto s = sim_hw_test::floor_only();
    s->meshes.push_back(sim_hw::make_grid_mesh("square", {0, 0, 0.2 + 0.1 * t}, Eigen::Vector3d::UnitX(),
                                               Eigen::Vector3d::UnitY(), 0.4, 0.4, 4, 4, {40, 40, 45}));
    return std::shared_ptr<const sim_hw::RenderScene>(s);
  };
}

sim_hw::SimulatedD415Camera make_camera(sim_hw::SimulatedD415Options o = {}) {
  if (!o.scene) o.scene = moving_scene();
  return sim_hw::SimulatedD415Camera(std::move(o));
}

void start(sim_hw::SimulatedD415Camera& cam, drivers::CameraConfig c = sim_hw_test::config_848("cam", sim_hw_test::looking_down(1.2))) {
  REQUIRE(cam.configure(c).ok);
  REQUIRE(cam.activate().ok);
}

// Centre pixel depth (mm): the square, at 1.2 - (0.2 + 0.1 t) m.
std::uint16_t centre(const drivers::DepthFrame& f) {
  return f.depth_mm[(f.depth_intrinsics.height / 2) * f.depth_intrinsics.width + f.depth_intrinsics.width / 2];
}

}  // namespace

TEST_CASE("simulated D415: lifecycle and a fully filled frame", "[camera_sim]") {
  auto cam = make_camera();
  drivers::DepthFrame f;
  CHECK(cam.read(f) == ReadStatus::kNotActive);
  auto bad = sim_hw_test::config_848("cam", sim_hw_test::looking_down(1.2));
  bad.depth_mode = {640, 480, 30};
  const auto r = cam.configure(bad);
  CHECK_FALSE(r.ok);
  CHECK_THAT(r.message, Catch::Contains("depth_mode 640x480@30") && Catch::Contains("848x480@30"));
  start(cam);
  CHECK(cam.health().state == drivers::CameraState::kActive);
  for (int i = 0; i < 3; ++i) {
    REQUIRE(cam.read(f) == ReadStatus::kFrame);
    CHECK(f.sequence == std::uint64_t(i));
    CHECK(cam.sim_time_s() == Approx(i / 30.0));
  }
  CHECK(f.camera == "cam");
  CHECK(f.depth_intrinsics.width == 848);
  CHECK(f.depth_intrinsics.fx == Approx(sim_hw::d415_depth_intrinsics({848, 480, 30}).fx));
  CHECK(f.depth_mm.size() == 848u * 480u);
  CHECK(f.color_intrinsics.width == 848);
  CHECK(f.rgb.size() == 3u * 848u * 480u);
  CHECK(f.depth_to_color.translation().x() == Approx(0.015));
  CHECK(f.camera_to_cell.isApprox(sim_hw_test::looking_down(1.2)));
  CHECK(f.device_time_us > 0);
  CHECK(int(centre(f)) == Approx(1000 - 100 * 2 / 30.0 + 1.0).margin(8));  // square + bias, noise
  // The dark square is dark in colour, the floor light.
  const auto& ck = f.color_intrinsics;
  CHECK(f.rgb[3 * ((ck.height / 2) * ck.width + ck.width / 2)] < 60);
  CHECK(f.rgb[3 * (10 * ck.width + 10)] > 100);
  CHECK(cam.health().frames == 3);
  CHECK(cam.deactivate().ok);
  CHECK(cam.read(f) == ReadStatus::kNotActive);
}

TEST_CASE("simulated D415: the same seed gives the same frames, another seed others", "[camera_sim]") {
  sim_hw::SimulatedD415Options o;
  o.seed = 42;
  auto a = make_camera(o), b = make_camera(o);
  o.seed = 43;
  auto c = make_camera(o);
  start(a);
  start(b);
  start(c);
  drivers::DepthFrame fa, fb, fc;
  for (int i = 0; i < 3; ++i) {
    REQUIRE(a.read(fa) == ReadStatus::kFrame);
    REQUIRE(b.read(fb) == ReadStatus::kFrame);
    REQUIRE(c.read(fc) == ReadStatus::kFrame);
    CHECK(fa.depth_mm == fb.depth_mm);
    CHECK(fa.rgb == fb.rgb);
    CHECK(fa.device_time_us == fb.device_time_us);
    CHECK(fa.depth_mm != fc.depth_mm);
  }
}

TEST_CASE("simulated D415: dropped frames leave sequence gaps or time out", "[camera_sim]") {
  auto cam = make_camera();
  start(cam);
  sim_hw::D415FaultConfig faults;
  faults.drop_every_nth = 3;  // frames 2, 5, 8 never arrive
  cam.set_faults(faults);
  drivers::DepthFrame f;
  std::vector<std::uint64_t> seq;
  for (int i = 0; i < 6; ++i) {
    REQUIRE(cam.read(f) == ReadStatus::kFrame);
    seq.push_back(f.sequence);
  }
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 3, 4, 6, 7});
  CHECK(cam.health().dropped == 2);
  // Every frame lost: nothing within read_timeout (200 ms).
  faults = {};
  faults.drop_probability = 1.0;
  cam.set_faults(faults);
  const double t0 = cam.sim_time_s();
  CHECK(cam.read(f) == ReadStatus::kTimeout);
  CHECK(cam.sim_time_s() == Approx(t0 + 0.2));
  CHECK(cam.health().timeouts == 1);
  CHECK(cam.health().state == drivers::CameraState::kDegraded);
  cam.set_faults({});
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  CHECK(cam.health().state == drivers::CameraState::kActive);
  // Random drops are seeded: at p = 0.3, about 43 dropped per 100 delivered.
  faults.drop_probability = 0.3;
  cam.set_faults(faults);
  const auto before = cam.health().dropped;
  for (int i = 0; i < 100; ++i) REQUIRE(cam.read(f) == ReadStatus::kFrame);
  CHECK(double(cam.health().dropped - before) == Approx(43).margin(15));
}

TEST_CASE("simulated D415: a frozen stream repeats its image with advancing counters", "[camera_sim]") {
  auto cam = make_camera();
  start(cam);
  drivers::DepthFrame f, before;
  for (int i = 0; i < 3; ++i) REQUIRE(cam.read(before) == ReadStatus::kFrame);
  sim_hw::D415FaultConfig faults;
  faults.frozen_from_s = cam.sim_time_s() + 1e-6;
  faults.frozen_until_s = faults.frozen_from_s + 0.2;
  cam.set_faults(faults);
  for (int i = 0; i < 5; ++i) {
    REQUIRE(cam.read(f) == ReadStatus::kFrame);  // the camera cannot tell; the monitor must
    CHECK(f.depth_mm == before.depth_mm);
    CHECK(f.rgb == before.rgb);
    CHECK(f.sequence == before.sequence + 1 + i);
    CHECK(f.device_time_us > before.device_time_us);
  }
  for (int i = 0; i < 3; ++i) REQUIRE(cam.read(f) == ReadStatus::kFrame);  // past the window
  CHECK(f.depth_mm != before.depth_mm);
  // Variant: the sequence counter and device clock stop too.
  faults.frozen_from_s = cam.sim_time_s() + 1e-6;
  faults.frozen_until_s = sim_hw::D415FaultConfig::kNever;
  faults.frozen_sequence_advances = false;
  cam.set_faults(faults);
  const auto last = f;
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  CHECK(f.sequence == last.sequence);
  CHECK(f.device_time_us == last.device_time_us);
  CHECK(f.depth_mm == last.depth_mm);
}

TEST_CASE("simulated D415: a dead camera reports kLost and comes back", "[camera_sim]") {
  sim_hw::SimulatedD415Options o;
  o.faults.dead_from_s = 0.1;
  o.faults.dead_until_s = 0.3;
  auto cam = make_camera(o);
  start(cam);
  drivers::DepthFrame f;
  int frames = 0, lost = 0;
  while (cam.sim_time_s() < 0.45) {
    const auto s = cam.read(f);
    if (s == ReadStatus::kFrame) {
      ++frames;
      CHECK((f.sequence < 3 || f.sequence >= 9));  // frames at t < 0.1 s or >= 0.3 s
    } else {
      REQUIRE(s == ReadStatus::kLost);
      ++lost;
      CHECK(cam.health().state == drivers::CameraState::kLost);
      CHECK_THAT(cam.health().message, Catch::Contains("lost"));
    }
  }
  CHECK(lost == 6);
  CHECK(frames == 9);  // t = 0 .. 0.4667 s: 15 reads
  CHECK(cam.health().reopened == 1);
  CHECK(cam.health().reopen_attempts == 6);
  CHECK(cam.health().state == drivers::CameraState::kActive);
}

TEST_CASE("simulated D415: stale timestamps stop or lag behind host time", "[camera_sim]") {
  SECTION("stopped device clock") {
    sim_hw::SimulatedD415Options o;
    o.faults.stale_from_s = 0.05;
    auto cam = make_camera(o);
    start(cam);
    drivers::DepthFrame f;
    std::vector<std::int64_t> device, host;
    for (int i = 0; i < 6; ++i) {
      REQUIRE(cam.read(f) == ReadStatus::kFrame);
      device.push_back(f.device_time_us);
      host.push_back(f.host_time_us);
    }
    CHECK(device[1] - device[0] == 33333);
    CHECK(device[2] == device[5]);  // from 0.05 s on: t = 0.0667 s onwards carry 0.05 s
    CHECK(host[5] - host[2] == 100000);
  }
  SECTION("lagging frames carry old content and old device time") {
    sim_hw::SimulatedD415Options o;
    o.faults.stale_from_s = 0.5;
    o.faults.stale_mode = sim_hw::StaleMode::kLagging;
    o.faults.stale_lag_s = 0.5;
    auto cam = make_camera(o);
    start(cam);
    drivers::DepthFrame f, first;
    REQUIRE(cam.read(first) == ReadStatus::kFrame);
    for (int i = 1; i <= 30; ++i) REQUIRE(cam.read(f) == ReadStatus::kFrame);  // t = 1.0 s
    CHECK(f.host_time_us - first.host_time_us == 1000000);
    CHECK(f.device_time_us - first.device_time_us == 500000);  // half a second behind
    CHECK(int(centre(f)) == Approx(1000 - 50 + 1).margin(8));  // the square as it was at 0.5 s
  }
}

TEST_CASE("simulated D415: wall clock paces reads at the frame rate", "[camera_sim]") {
  sim_hw::SimulatedD415Options o;
  o.clock = sim_hw::SimClock::kWall;
  auto cam = make_camera(o);
  start(cam);
  drivers::DepthFrame f;
  const auto t0 = std::chrono::steady_clock::now();
  std::int64_t first_host = 0;
  for (int i = 0; i < 4; ++i) {
    REQUIRE(cam.read(f) == ReadStatus::kFrame);
    if (i == 0) first_host = f.host_time_us;
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(elapsed >= 0.09);  // frames 1..3 due at 33, 67, 100 ms
  CHECK(f.host_time_us - first_host >= 90000);
  CHECK(f.sequence >= 3);
}

TEST_CASE("simulated D415: sees the twin's sheet where it hangs", "[camera_sim]") {
  // A 1 m sheet of ~6k triangles hanging in the plane y = 0 from z = 1.5 m; the camera 1.5 m in
  // front (-y) at z = 1.0 m looking along +y. Without noise every sheet pixel reads 1500 mm.
  const twin::SheetMesh sheet = twin::make_rectangular_sheet(1.0, 1.0, twin::edge_length_for_triangle_count(1.0, 1.0, 6000));
  twin::VecX x(3 * sheet.vertex_count());
  for (int i = 0; i < sheet.vertex_count(); ++i) {
    x.segment<3>(3 * i) = Eigen::Vector3d(sheet.rest_uv[i].x() - 0.5, 0.0, 1.5 - sheet.rest_uv[i].y());
  }
  auto scene = sim_hw_test::floor_only();
  scene->meshes.push_back(sim_hw::sheet_scene_mesh(sheet, x));
  CHECK(scene->meshes[0].triangles.size() > 5000);
  sim_hw::SimulatedD415Options o;
  o.scene = [scene](double) { return scene; };
  o.noise.sigma_at_1m_mm = o.noise.bias_at_1m_mm = o.noise.dropout_fraction = 0;
  auto cam = make_camera(o);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  pose.translation() = Eigen::Vector3d(0, -1.5, 1.0);
  start(cam, sim_hw_test::config_848("front", pose));
  drivers::DepthFrame f;
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  const auto& k = f.depth_intrinsics;
  int on_sheet = 0;
  for (int r = 0; r < k.height; ++r) {
    for (int c = 0; c < k.width; ++c) {
      // Pixel ray hits y = 0 at cell x = 1.5 (c - cx) / fx, z = 1.0 - 1.5 (r - cy) / fy.
      const double cx = 1.5 * (c - k.cx) / k.fx, cz = 1.0 - 1.5 * (r - k.cy) / k.fy;
      if (std::abs(cx) < 0.48 && cz > 0.52 && cz < 1.48 && c > 40) {  // inside, off the borders
        ++on_sheet;
        REQUIRE(f.depth_mm[r * k.width + c] == 1500);
      }
    }
  }
  CHECK(on_sheet > 50000);
  CHECK_THROWS_WITH(sim_hw::update_sheet_vertices(scene->meshes[0], twin::VecX(6)), Catch::Contains("expected 3 per vertex"));
}

TEST_CASE("simulated D415: depth_to_color maps depth pixels onto their colour", "[camera_sim]") {
  // What a tracker does to colour its points: deproject each depth pixel, move it with
  // depth_to_color, project with the colour intrinsics. The dark square (1.0 m away) must come
  // out dark and the floor (1.2 m) light; a wrong sign of the 15 mm offset would smear ~10 px.
  sim_hw::SimulatedD415Options o;
  o.noise.sigma_at_1m_mm = o.noise.bias_at_1m_mm = 0;
  auto cam = make_camera(o);
  auto config = sim_hw_test::config_848("aligned", sim_hw_test::looking_down(1.2));
  config.color_mode = {1280, 720, 30};  // a different resolution and field of view than depth
  start(cam, config);
  drivers::DepthFrame f;
  REQUIRE(cam.read(f) == ReadStatus::kFrame);
  const auto& dk = f.depth_intrinsics;
  const auto& ck = f.color_intrinsics;
  int square = 0, floor = 0, wrong = 0;
  for (int r = 0; r < dk.height; ++r) {
    for (int c = 0; c < dk.width; ++c) {
      const std::uint16_t d = f.depth_mm[r * dk.width + c];
      if (d == 0) continue;
      const double z = d / 1000.0;
      const Eigen::Vector3d p = f.depth_to_color * Eigen::Vector3d((c - dk.cx) / dk.fx * z, (r - dk.cy) / dk.fy * z, z);
      const int u = int(std::lround(ck.fx * p.x() / p.z() + ck.cx)), v = int(std::lround(ck.fy * p.y() / p.z() + ck.cy));
      if (u < 0 || v < 0 || u >= ck.width || v >= ck.height) continue;
      const int red = f.rgb[3 * (v * ck.width + u)];
      if (std::abs(z - 1.0) < 0.01) {
        ++square;
        wrong += red > 60;
      } else if (std::abs(z - 1.2) < 0.01) {
        ++floor;
        wrong += red < 100;
      }
    }
  }
  CHECK(square > 20000);
  CHECK(floor > 100000);
  CHECK(wrong < 0.002 * (square + floor));
}
