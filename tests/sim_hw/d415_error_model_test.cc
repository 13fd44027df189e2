// The D415 error model: noise RMS ~ z^2 (1.5 mm at 1 m, 6 mm at 2 m), bias, quantisation, and the
// invalid pixels (grazing angle, stereo shadow, range, dropout, edges).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "sim_hw/d415_error_model.h"
#include "sim_hw/d415_model.h"
#include "tests/sim_hw/d415_test_scenes.h"

namespace {

const Eigen::Isometry3d kRightInLeft(Eigen::Translation3d(sim_hw::kD415BaselineM, 0, 0));

struct Stats {
  double mean_mm = 0, rms_mm = 0;
  double valid_fraction = 0;
};

// Depth of a floor plane seen straight down from height_m: every true depth is height_m exactly.
Stats fronto_parallel(double height_m, sim_hw::D415NoiseConfig noise, std::uint64_t seed) {
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  sim_hw::RenderedView view;
  sim_hw::render_view(*sim_hw_test::floor_only(), sim_hw_test::looking_down(height_m), k, view);
  std::mt19937_64 rng(seed);
  std::vector<std::uint16_t> depth;
  sim_hw::make_depth_image(view, nullptr, k, kRightInLeft, noise, 1.0, rng, depth);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (const auto d : depth) {
    if (d == 0) continue;
    const double e = d - 1000.0 * height_m;
    sum += e;
    sum2 += e * e;
    ++n;
  }
  Stats s;
  s.mean_mm = sum / n;
  s.rms_mm = std::sqrt(sum2 / n - s.mean_mm * s.mean_mm);
  s.valid_fraction = double(n) / depth.size();
  return s;
}

}  // namespace

TEST_CASE("error model: depth noise RMS grows with distance squared", "[camera_sim]") {
  sim_hw::D415NoiseConfig noise;
  noise.bias_at_1m_mm = 0;
  const Stats at1 = fronto_parallel(1.0, noise, 7);
  const Stats at2 = fronto_parallel(2.0, noise, 8);
  CHECK(at1.rms_mm == Approx(1.5).epsilon(0.15));
  CHECK(at2.rms_mm == Approx(6.0).epsilon(0.15));
  CHECK(std::abs(at1.mean_mm) < 0.05);
  CHECK(std::abs(at2.mean_mm) < 0.1);
  // Dropout 0.2 %: almost everything valid on a plain fronto-parallel floor.
  CHECK(at1.valid_fraction > 0.99);
  CHECK(at1.valid_fraction < 0.9995);
}

TEST_CASE("error model: the configured bias scales with distance squared", "[camera_sim]") {
  sim_hw::D415NoiseConfig noise;  // default bias +1 mm at 1 m
  CHECK(fronto_parallel(1.0, noise, 1).mean_mm == Approx(1.0).margin(0.05));
  CHECK(fronto_parallel(2.0, noise, 2).mean_mm == Approx(4.0).margin(0.1));
  noise.bias_at_1m_mm = -2.0;
  CHECK(fronto_parallel(1.5, noise, 3).mean_mm == Approx(-4.5).margin(0.1));
}

TEST_CASE("error model: without noise depth is the truth quantised to whole units", "[camera_sim]") {
  sim_hw::D415NoiseConfig noise;
  noise.sigma_at_1m_mm = noise.bias_at_1m_mm = noise.dropout_fraction = 0;
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  Eigen::Isometry3d pose = sim_hw_test::looking_down(1.2345);
  pose.linear() = pose.linear() * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  sim_hw::RenderedView view;
  sim_hw::render_view(*sim_hw_test::floor_only(), pose, k, view);
  std::mt19937_64 rng(1);
  for (const double unit : {1.0, 0.5}) {
    std::vector<std::uint16_t> depth;
    sim_hw::make_depth_image(view, nullptr, k, kRightInLeft, noise, unit, rng, depth);
    for (std::size_t i = 0; i < depth.size(); i += 97) {
      REQUIRE(depth[i] == std::lround(1000.0 * view.depth_m[i] / unit));
    }
  }
}

TEST_CASE("error model: grazing surfaces and out-of-range pixels are invalid", "[camera_sim]") {
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  // Looking almost horizontally over a floor: the far rows are seen at grazing angles.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(-0.25, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                  (Eigen::Matrix3d() << 1, 0, 0, 0, 0, 1, 0, -1, 0).finished();
  pose.translation() = Eigen::Vector3d(0, 0, 0.8);
  sim_hw::RenderedView view;
  sim_hw::render_view(*sim_hw_test::floor_only(), pose, k, view);
  sim_hw::D415NoiseConfig noise;
  noise.dropout_fraction = 0;
  std::mt19937_64 rng(5);
  std::vector<std::uint16_t> depth;
  sim_hw::make_depth_image(view, nullptr, k, kRightInLeft, noise, 1.0, rng, depth);
  int grazing = 0, grazing_valid = 0, steep = 0, steep_valid = 0;
  for (int r = 0; r < k.height; ++r) {
    for (int c = 1; c + 1 < k.width; ++c) {
      const std::size_t i = r * k.width + c;
      const float z = view.depth_m[i];
      if (z == 0.0f || z > 9.5f || z < 0.35f) continue;
      const Eigen::Vector3d ray = Eigen::Vector3d((c - k.cx) / k.fx, (r - k.cy) / k.fy, 1).normalized();
      const double angle = std::acos(std::abs(view.normal_cam[i].cast<double>().dot(ray))) * 180 / M_PI;
      if (angle > 80.5) {
        ++grazing;
        grazing_valid += depth[i] != 0;
      } else if (angle < 79.5) {
        ++steep;
        steep_valid += depth[i] != 0;
      }
    }
  }
  CHECK(grazing > 1000);
  CHECK(grazing_valid == 0);
  CHECK(steep > 1000);
  CHECK(steep_valid > 0.99 * steep);
  // Beyond max range (10 m) the floor is never reported.
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (view.depth_m[i] > 10.0f) REQUIRE(depth[i] == 0);
  }
}

TEST_CASE("error model: the stereo shadow beside an occluder and its edges are invalid", "[camera_sim]") {
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  // Camera frame = cell frame; a wall at z = 2 m (the floor plane) and a box 1.0-1.1 m away.
  sim_hw::RenderScene scene = *sim_hw_test::floor_only();
  scene.floor->height_m = 2.0;
  scene.meshes.push_back(sim_hw::make_box_mesh("box", {-0.1, -0.1, 1.0}, {0.1, 0.1, 1.1}, {200, 0, 0}));
  sim_hw::RenderedView left, right;
  sim_hw::render_view(scene, Eigen::Isometry3d::Identity(), k, left);
  sim_hw::render_view(scene, kRightInLeft, k, right);
  sim_hw::D415NoiseConfig noise;
  noise.dropout_fraction = 0;
  std::mt19937_64 rng(5);
  std::vector<std::uint16_t> with, without;
  sim_hw::make_depth_image(left, &right, k, kRightInLeft, noise, 1.0, rng, with);
  sim_hw::make_depth_image(left, nullptr, k, kRightInLeft, noise, 1.0, rng, without);
  // The right imager (+x) cannot see the wall for x in about (-0.255, -0.2) m at z = 2 m, i.e.
  // columns cx - 84.8 .. cx - 66.5 on the centre row; the mirror strip (+x side) stays visible.
  const int r = int(k.cy);
  int shadow_cols = 0;
  for (double x = -0.25; x <= -0.205; x += 0.002) {
    const int c = int(std::lround(k.cx + k.fx * x / 2.0));
    REQUIRE(with[r * k.width + c] == 0);
    REQUIRE(without[r * k.width + c] != 0);
    const int c_mirror = int(std::lround(k.cx - k.fx * x / 2.0));
    REQUIRE(with[r * k.width + c_mirror] != 0);
    ++shadow_cols;
  }
  CHECK(shadow_cols > 15);
  // Depth edges: pixels right next to the box outline (a 0.9 m jump) are invalid, the box centre valid.
  const int c_edge = int(std::ceil(k.cx + k.fx * 0.1 / 1.0));  // first wall pixel right of the box front
  CHECK((without[r * k.width + c_edge] == 0 || without[r * k.width + c_edge - 1] == 0));
  CHECK(without[r * k.width + int(k.cx)] != 0);
}

TEST_CASE("error model: colour is shaded albedo with slight noise", "[camera_sim]") {
  const auto k = sim_hw::d415_color_intrinsics({848, 480, 30});
  sim_hw::RenderScene scene = *sim_hw_test::floor_only();
  scene.light_direction_cell = Eigen::Vector3d::UnitZ();  // straight down onto the floor
  sim_hw::RenderedView view;
  sim_hw::render_view(scene, sim_hw_test::looking_down(1.0), k, view);
  sim_hw::D415NoiseConfig noise;
  std::mt19937_64 rng(9);
  std::vector<std::uint8_t> rgb;
  sim_hw::make_color_image(view, scene, Eigen::Vector3d(0, 0, -1), noise, rng, rgb);
  REQUIRE(rgb.size() == 3u * k.width * k.height);
  double sum = 0, sum2 = 0;
  const std::size_t n = rgb.size() / 3;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = rgb[3 * i] - 170.0;  // full light: albedo
    sum += e;
    sum2 += e * e;
  }
  CHECK(std::abs(sum / n) < 0.05);
  CHECK(std::sqrt(sum2 / n) == Approx(2.0).epsilon(0.15));
}
