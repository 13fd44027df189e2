// Stages 1-2 of the tracker against analytic scenes: fused geometry is exact without noise,
// colour is looked up through depth_to_color, corrupt frames are rejected with a status, and
// segmentation keeps the sheet by box and colour.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <memory>

#include "tests/tracking/analytic_scene.h"
#include "tracking/depth_fusion.h"
#include "tracking/sheet_segmentation.h"

namespace tracking {
namespace {

using testing::CameraSetup;
using testing::NoiseModel;
using testing::Rgb;
using testing::Scene;

// Each point's distance to the nearest surface of the scene (m).
double distance_to_scene(const Scene& scene, const Eigen::Vector3f& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : scene.surfaces) best = std::min(best, s->distance(p.cast<double>()));
  return best;
}

Scene plane_and_cylinder() {
  Scene scene;
  scene.surfaces.push_back(std::make_shared<const testing::PlaneSurface>(
      Vec3(0, 0, 0.5), Vec3::UnitX(), Vec3(0, 1, 0.3), 0.6, 0.6, Rgb{30, 30, 30}));
  scene.surfaces.push_back(std::make_shared<const testing::CylinderSurface>(
      Vec3(0.1, 0, 0.75), Vec3::UnitY(), 0.1, 0.3, Rgb{200, 60, 40}));
  return scene;
}

}  // namespace

TEST_CASE("fusion puts noise-free pixels on the analytic surfaces, distorted lens included",
          "[tracker][fusion]") {
  const Scene scene = plane_and_cylinder();
  CameraSetup cam = testing::look_at_camera("cam", Vec3(0.3, -0.9, 1.6), Vec3(0, 0, 0.6), 424, 240);
  const bool distorted = GENERATE(false, true);
  if (distorted) {
    cam.depth.k1 = -0.08;
    cam.depth.k2 = 0.02;
    cam.depth.p1 = 0.001;
    cam.depth.p2 = -0.0005;
    cam.color.k1 = 0.06;  // the colour lookup goes through the forward model
    cam.color.p1 = -0.001;
  }
  const drivers::DepthFrame frame = testing::render_frame(scene, cam, NoiseModel{0.0, 1});
  DepthFusion fusion;
  FusionOptions every_pixel;
  every_pixel.pixel_stride = 1;
  fusion.set_options(every_pixel);
  SensorCloud cloud;
  const FrameReport report = fusion.add_frame(frame, 2, cloud);
  REQUIRE(report.status == FrameStatus::kOk);
  REQUIRE(report.color_used);
  REQUIRE(report.points > 20000);
  double worst = 0.0;
  int cylinder_coloured = 0, cylinder_points = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    // Depth is whole millimetres: at most 0.5 mm along a ray whose length is at most ~1.3 z.
    worst = std::max(worst, distance_to_scene(scene, cloud.points_m[i]));
    CHECK(cloud.camera[i] == 2);
    if (scene.surfaces[1]->distance(cloud.points_m[i].cast<double>()) < 1e-3 &&
        scene.surfaces[0]->distance(cloud.points_m[i].cast<double>()) > 0.01) {
      ++cylinder_points;
      if (cloud.has_color[i] && cloud.rgb[3 * i] == 200) ++cylinder_coloured;
    }
  }
  CHECK(worst < 0.8e-3);
  // Colour through depth_to_color: the cylinder's own points carry its colour, except a few at
  // its silhouette that the colour camera, 15 mm aside, sees differently.
  REQUIRE(cylinder_points > 1000);
  CHECK(cylinder_coloured > 0.97 * cylinder_points);
}

TEST_CASE("pixel stride decimates the frame", "[tracker][fusion]") {
  const Scene scene = plane_and_cylinder();
  const CameraSetup cam =
      testing::look_at_camera("cam", Vec3(0, -0.8, 1.5), Vec3(0, 0, 0.6), 424, 240);
  const drivers::DepthFrame frame = testing::render_frame(scene, cam, NoiseModel{});
  DepthFusion full, half;
  FusionOptions o;
  o.pixel_stride = 1;
  full.set_options(o);
  o.pixel_stride = 2;
  half.set_options(o);
  SensorCloud a, b;
  const int na = full.add_frame(frame, 0, a).points, nb = half.add_frame(frame, 0, b).points;
  CHECK(nb == Approx(na / 4.0).epsilon(0.05));
}

TEST_CASE("corrupt frames are rejected with a clear status", "[tracker][fusion]") {
  const Scene scene = plane_and_cylinder();
  const CameraSetup cam =
      testing::look_at_camera("cam", Vec3(0, -0.8, 1.5), Vec3(0, 0, 0.6), 160, 120);
  const drivers::DepthFrame good = testing::render_frame(scene, cam, NoiseModel{});
  DepthFusion fusion;
  SensorCloud cloud;
  REQUIRE(fusion.add_frame(good, 0, cloud).status == FrameStatus::kOk);
  const std::size_t before = cloud.size();

  drivers::DepthFrame bad = good;
  FrameStatus expected = FrameStatus::kOk;
  SECTION("wrong depth size") {
    bad.depth_mm.resize(bad.depth_mm.size() - 7);
    expected = FrameStatus::kSizeMismatch;
  }
  SECTION("no depth image") {
    bad.depth_mm.clear();
    expected = FrameStatus::kEmpty;
  }
  SECTION("all zero") {
    std::fill(bad.depth_mm.begin(), bad.depth_mm.end(), 0);
    expected = FrameStatus::kEmpty;
  }
  SECTION("NaN extrinsics") {
    bad.camera_to_cell.translation().x() = std::numeric_limits<double>::quiet_NaN();
    expected = FrameStatus::kNonFinitePose;
  }
  SECTION("extrinsics not a rotation") {
    bad.camera_to_cell.linear()(0, 0) *= 1.5;
    expected = FrameStatus::kNonFinitePose;
  }
  SECTION("zero focal length") {
    bad.depth_intrinsics.fx = 0.0;
    expected = FrameStatus::kBadIntrinsics;
  }
  SECTION("infinite principal point") {
    bad.depth_intrinsics.cy = std::numeric_limits<double>::infinity();
    expected = FrameStatus::kBadIntrinsics;
  }
  const FrameReport report = fusion.add_frame(bad, 1, cloud);
  CHECK(report.status == expected);
  CHECK_FALSE(report.message.empty());
  CHECK(report.points == 0);
  CHECK(cloud.size() == before);  // nothing of a rejected frame gets in
}

TEST_CASE("colour of the wrong size is ignored but depth is kept", "[tracker][fusion]") {
  const Scene scene = plane_and_cylinder();
  const CameraSetup cam =
      testing::look_at_camera("cam", Vec3(0, -0.8, 1.5), Vec3(0, 0, 0.6), 160, 120);
  drivers::DepthFrame frame = testing::render_frame(scene, cam, NoiseModel{});
  frame.rgb.resize(frame.rgb.size() / 2);
  DepthFusion fusion;
  SensorCloud cloud;
  const FrameReport report = fusion.add_frame(frame, 0, cloud);
  CHECK(report.status == FrameStatus::kOk);
  CHECK_FALSE(report.color_used);
  CHECK(report.message.find("colour ignored") != std::string::npos);
  CHECK(report.points > 1000);
  for (std::uint8_t c : cloud.has_color) CHECK(c == 0);
}

TEST_CASE("segmentation keeps the dark sheet inside the box", "[tracker][segmentation]") {
  std::shared_ptr<const testing::SaggingSheet> sheet;
  Scene scene = testing::sheet_scene(testing::SheetShape{}, &sheet);
  // A bright gripper-like cylinder at the sheet's edge, inside the workspace box.
  scene.surfaces.push_back(std::make_shared<const testing::CylinderSurface>(
      Vec3(0.55, 0, 0.95), Vec3::UnitY(), 0.04, 0.2, Rgb{210, 70, 40}));
  const CameraSetup cam =
      testing::look_at_camera("cam", Vec3(0, -1.1, 1.9), Vec3(0, 0, 0.8), 424, 240);
  const drivers::DepthFrame frame = testing::render_frame(scene, cam, NoiseModel{0.0, 3});
  DepthFusion fusion;
  SensorCloud cloud;
  REQUIRE(fusion.add_frame(frame, 0, cloud).status == FrameStatus::kOk);

  SegmentationOptions options;
  options.box_min_m = Vec3(-0.8, -0.7, 0.5);
  options.box_max_m = Vec3(0.8, 0.7, 1.3);
  SegmentationCounts counts;
  const SensorCloud kept = segment_sheet(cloud, options, &counts);
  CHECK(counts.outside_box > 1000);  // the floor
  CHECK(counts.wrong_color > 100);   // the gripper
  const auto on_sheet = [&](const Eigen::Vector3f& p) {
    return sheet->distance(p.cast<double>()) < 2e-3;
  };
  int sheet_points = 0;
  for (const Eigen::Vector3f& p : cloud.points_m) sheet_points += on_sheet(p);
  int kept_on_sheet = 0;
  for (const Eigen::Vector3f& p : kept.points_m) kept_on_sheet += on_sheet(p);
  CHECK(kept_on_sheet == Approx(kept.size()).epsilon(0.005));  // nearly nothing else kept
  CHECK(kept_on_sheet == Approx(sheet_points).epsilon(0.02));  // nearly all the sheet kept

  SECTION("cropping to the box while fusing drops exactly what the box would, and counts it") {
    DepthFusion cropping;
    FusionOptions o;
    o.crop_to_box = true;
    o.box_min_m = options.box_min_m.cast<float>();
    o.box_max_m = options.box_max_m.cast<float>();
    cropping.set_options(o);
    SensorCloud cropped;
    const FrameReport report = cropping.add_frame(frame, 0, cropped);
    REQUIRE(report.status == FrameStatus::kOk);
    CHECK(report.outside_box == counts.outside_box);
    CHECK(report.points == counts.input - counts.outside_box);
    SegmentationCounts c;
    CHECK(segment_sheet(cropped, options, &c).size() == kept.size());
    CHECK(c.outside_box == 0);
  }

  SECTION("points without colour follow the policy") {
    SensorCloud uncoloured = cloud;
    std::fill(uncoloured.has_color.begin(), uncoloured.has_color.end(), 0);
    SegmentationCounts c;
    CHECK(segment_sheet(uncoloured, options, &c).size() == cloud.size() - counts.outside_box);
    options.color.unknown = UnknownColorPolicy::kReject;
    CHECK(segment_sheet(uncoloured, options, &c).size() == 0);
    CHECK(c.unknown_color == counts.input - counts.outside_box);
  }
}

TEST_CASE("colour rule: value ceiling, saturation and a hue range through red",
          "[tracker][segmentation]") {
  ColorRule rule;
  CHECK(color_passes(rule, 30, 30, 30));
  CHECK_FALSE(color_passes(rule, 200, 200, 200));
  rule.max_value = 1.0;
  rule.use_hue = true;
  rule.min_hue_deg = 340;  // wraps through 0
  rule.max_hue_deg = 20;
  CHECK(color_passes(rule, 200, 40, 40));          // red, hue 0
  CHECK(color_passes(rule, 200, 40, 80));          // hue 345
  CHECK_FALSE(color_passes(rule, 40, 200, 40));    // green
  CHECK_FALSE(color_passes(rule, 100, 100, 100));  // grey has no hue
  rule.use_hue = false;
  rule.min_saturation = 0.5;
  CHECK_FALSE(color_passes(rule, 100, 90, 90));
  CHECK(color_passes(rule, 100, 20, 20));
}

}  // namespace tracking
