// The calibration check passes a correct camera set and flags a camera whose extrinsic is off
// by 1 cm or 1 degree, through the tracker's own path (its first cycle runs the check).
#include <catch2/catch.hpp>

#include <cmath>

#include "tests/tracking/analytic_scene.h"
#include "tracking/sheet_tracker.h"

namespace tracking {
namespace {

std::vector<drivers::DepthFrame> frames_with_cam_left_off(
    const Eigen::Isometry3d& error_in_camera) {
  testing::SheetShape shape;
  shape.slope_x = 0.04;
  const testing::Scene scene = testing::sheet_scene(shape);
  const auto cameras = testing::three_cameras(848, 480);
  std::vector<drivers::DepthFrame> frames;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    frames.push_back(
        testing::render_frame(scene, cameras[c], {0.0015, static_cast<std::uint32_t>(21 + c)}));
  }
  // The camera really is where it was rendered from; its configured extrinsic is wrong.
  frames[2].camera_to_cell = frames[2].camera_to_cell * error_in_camera;
  return frames;
}

std::vector<CameraPairAgreement> check(const std::vector<drivers::DepthFrame>& frames) {
  TrackerConfig config;
  config.segmentation.box_min_m = Vec3(-0.9, -0.8, 0.5);
  config.segmentation.box_max_m = Vec3(0.9, 0.8, 1.3);
  SheetTracker tracker(config);
  const SurfaceMesh prediction = testing::SaggingSheet({}, {0, 0, 0}).mesh(30, 25);
  const TrackResult r = tracker.track(frames, prediction);
  REQUIRE(r.status == TrackStatus::kOk);
  REQUIRE(r.calibration_checked);
  REQUIRE(r.calibration.size() == 3);
  for (const CameraPairAgreement& p : r.calibration) {
    INFO("pair " << p.camera_a << "-" << p.camera_b << ": " << p.overlap_points
                 << " points, median " << p.median_m << " p90 " << p.p90_m);
    CHECK(p.judged);  // every pair overlaps in this cell
  }
  return r.calibration;
}

}  // namespace

TEST_CASE("calibration check passes a correct camera set", "[tracker][calibration]") {
  for (const CameraPairAgreement& p :
       check(frames_with_cam_left_off(Eigen::Isometry3d::Identity()))) {
    INFO("pair " << p.camera_a << "-" << p.camera_b << " median " << p.median_m << " p90 "
                 << p.p90_m);
    CHECK_FALSE(p.flagged);
    CHECK(p.median_m < 0.002);
  }
}

TEST_CASE("calibration check flags a camera 1 cm or 1 degree off", "[tracker][calibration]") {
  Eigen::Isometry3d error = Eigen::Isometry3d::Identity();
  SECTION("1 cm along the optical axis") { error.translation() = Vec3(0, 0, 0.01); }
  SECTION("1 cm sideways and up in the image") { error.translation() = Vec3(0.007, -0.007, 0); }
  SECTION("1 degree about the image x axis") {
    error.linear() = Eigen::AngleAxisd(M_PI / 180.0, Vec3::UnitX()).toRotationMatrix();
  }
  SECTION("1 degree about the optical axis") {
    error.linear() = Eigen::AngleAxisd(M_PI / 180.0, Vec3::UnitZ()).toRotationMatrix();
  }
  for (const CameraPairAgreement& p : check(frames_with_cam_left_off(error))) {
    INFO("pair " << p.camera_a << "-" << p.camera_b << " median " << p.median_m << " p90 "
                 << p.p90_m);
    // cam_left is camera 2: both its pairs disagree, the other pair still agrees.
    CHECK(p.flagged == (p.camera_b == 2));
  }
}

}  // namespace tracking
