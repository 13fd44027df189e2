// The running cell's calibration check: judged only while the sheet is still, off the cycle,
// and reported after three disagreeing checks in a row.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "cell/calibration_monitor.h"

namespace {

// Two cameras' points on the plane z = 1 m (0.4 x 0.4 m, 5 mm apart); camera 1's points are
// offset_m higher, as from a camera knocked on its mount.
tracking::SensorCloud two_camera_plane(double offset_m) {
  tracking::SensorCloud c;
  for (int cam = 0; cam < 2; ++cam) {
    for (double x = -0.2; x <= 0.2; x += 0.005) {
      for (double y = -0.2; y <= 0.2; y += 0.005) {
        // Camera 1 samples between camera 0's points, so no point is simply repeated.
        const double shift = cam == 1 ? 0.0025 : 0.0;
        c.points_m.emplace_back(x + shift, y + shift, 1.0 + (cam == 1 ? offset_m : 0.0));
        c.rgb.insert(c.rgb.end(), {20, 20, 20});
        c.has_color.push_back(1);
        c.camera.push_back(static_cast<std::uint8_t>(cam));
      }
    }
  }
  return c;
}

// Feeds tracked cycles (the sheet at `speed`) until `checks` more checks have finished. Each
// cycle waits for the check it started, so the next cycle takes it up and starts another: the
// checks finish one a cycle whatever the machine's speed.
void cycles_until_checked(cell::CalibrationMonitor& m, const tracking::SensorCloud& cloud, double speed, int checks) {
  const std::vector<std::string> names{"cam_a", "cam_b"};
  const int target = m.checks_finished() + checks;
  // One cycle to start the first check, then one per check; a few more would not help.
  for (int cycle = 0; cycle < checks + 2 && m.checks_finished() < target; ++cycle) {
    m.after_tracked_cycle(cloud, names, speed);
    m.wait_for_running_check();
  }
  REQUIRE(m.checks_finished() >= target);
}

tracking::CalibrationCheckOptions every_cycle() {
  tracking::CalibrationCheckOptions o;
  o.every_n_cycles = 1;
  return o;
}

}  // namespace

TEST_CASE("calibration monitor: a knocked camera is reported after three checks in a row, cleared at once", "[cell]") {
  cell::CalibrationMonitor m(every_cycle());
  const auto agree = two_camera_plane(0.0), knocked = two_camera_plane(0.01);
  CHECK(m.check_now(agree, {"cam_a", "cam_b"}).empty());
  cycles_until_checked(m, knocked, 0.0, 2);
  CHECK(m.problem().empty());  // two disagreeing checks: not yet
  cycles_until_checked(m, knocked, 0.0, 1);
  CHECK_THAT(m.problem(), Catch::Contains("cam_a and cam_b disagree"));
  // (The check running when the camera is put back saw the knocked cloud: two checks.)
  cycles_until_checked(m, agree, 0.0, 2);
  CHECK(m.problem().empty());
  // At start-up one check decides.
  CHECK_THAT(m.check_now(knocked, {"cam_a", "cam_b"}), Catch::Contains("disagree"));
}

TEST_CASE("calibration monitor: no check while the sheet moves", "[cell]") {
  cell::CalibrationMonitor m(every_cycle());
  const auto knocked = two_camera_plane(0.01);
  const std::vector<std::string> names{"cam_a", "cam_b"};
  for (int i = 0; i < 50; ++i) {
    m.after_tracked_cycle(knocked, names, 2 * cell::kStillSheetSpeedMS);
    m.after_tracked_cycle(knocked, names, std::numeric_limits<double>::infinity());  // speed unknown
    // A check started by mistake would finish here and be counted by the next cycle.
    CHECK_FALSE(m.wait_for_running_check());
  }
  CHECK(m.checks_finished() == 0);
  CHECK(m.problem().empty());
}

TEST_CASE("calibration monitor: the sheet's speed is the median vertex move over the frames' interval", "[cell]") {
  std::vector<Eigen::Vector3d> before(5, Eigen::Vector3d::Zero()), after = before;
  after[0].x() = 1.0;  // one vertex jumps (a registration outlier): the median ignores it
  after[1].x() = 0.003;
  CHECK(cell::median_vertex_speed_m_s(before, after, 0.1) == Approx(0.0));
  after[2].x() = after[3].x() = 0.003;
  CHECK(cell::median_vertex_speed_m_s(before, after, 0.1) == Approx(0.03));
  CHECK(std::isinf(cell::median_vertex_speed_m_s({}, after, 0.1)));
  CHECK(std::isinf(cell::median_vertex_speed_m_s(before, after, 0.0)));
}
