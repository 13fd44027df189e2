// Successive tracker cycles: a cycle after one that tracked starts its registration from that
// result, moved as the prediction moved (registration.warm_start), and so needs fewer
// iterations for the same surface; when the sheet moved farther than the warm gate, or the
// last cycle did not track, or the prediction is on another mesh, it starts from the prediction.
#include <catch2/catch.hpp>

#include <cmath>

#include "tests/tracking/analytic_scene.h"
#include "tracking/sheet_tracker.h"

namespace tracking {
namespace {

using testing::SheetShape;

SheetShape true_shape(double z0_m) {
  SheetShape s;
  s.z0_m = z0_m;
  s.slope_x = 0.04;
  s.ripple_m = 0.015;
  return s;
}

// Up to ~4 cm off the truth at the same height: less sag, no tilt or ripple.
SheetShape predicted_shape(double z0_m) {
  SheetShape s;
  s.z0_m = z0_m;
  s.sag_m = 0.085;
  return s;
}

struct View {
  std::shared_ptr<const testing::SaggingSheet> sheet;
  std::vector<drivers::DepthFrame> frames;
};

// The three test cameras on the sheet at height z0_m, noise seeded by `seed`.
View view(double z0_m, std::uint32_t seed) {
  View v;
  const testing::Scene scene = testing::sheet_scene(true_shape(z0_m), &v.sheet);
  const auto cameras = testing::three_cameras(848, 480);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    v.frames.push_back(testing::render_frame(
        scene, cameras[c], testing::NoiseModel{0.0015, static_cast<std::uint32_t>(seed + c)}));
  }
  return v;
}

SurfaceMesh prediction(double z0_m, int cols = 40, int rows = 34) {
  return testing::SaggingSheet(predicted_shape(z0_m), {0, 0, 0}).mesh(cols, rows);
}

TrackerConfig config() {
  TrackerConfig c;
  c.segmentation.box_min_m = Vec3(-0.9, -0.8, 0.4);
  c.segmentation.box_max_m = Vec3(0.9, 0.8, 1.3);
  return c;
}

double mean_error(const View& v, const TrackResult& r) {
  double sum = 0.0;
  for (const Vec3& x : r.vertices_m) sum += v.sheet->distance(x);
  return sum / r.vertices_m.size();
}

}  // namespace

TEST_CASE("cycles after a tracked one start from its result: fewer iterations, same surface",
          "[tracker][warm]") {
  // The same sheet seen with two noise draws, alternately, as a held ply is cycle after cycle.
  const View first = view(0.9, 11), second = view(0.9, 21);
  SheetTracker tracker(config());
  const TrackResult a = tracker.track(first.frames, prediction(0.9));
  REQUIRE(a.status == TrackStatus::kOk);
  CHECK_FALSE(a.registration_warm);
  // Each warm cycle continues where the last one stopped (a cold fit ends its six iterations
  // still moving 0.2-0.3 mm RMS an iteration); after a few the fits end at the convergence test.
  TrackResult b;
  for (int cycle = 1; cycle <= 4; ++cycle) {
    b = tracker.track(cycle % 2 ? second.frames : first.frames, prediction(0.9));
    REQUIRE(b.status == TrackStatus::kOk);
    CHECK(b.registration_warm);
    CHECK_FALSE(b.registration_restarted);
  }

  TrackerConfig cold_config = config();
  cold_config.registration.warm_start = false;
  SheetTracker cold(cold_config);
  const TrackResult c = cold.track(first.frames, prediction(0.9));
  REQUIRE(c.status == TrackStatus::kOk);
  CHECK_FALSE(c.registration_warm);
  INFO("iterations warm " << b.registration_iterations << " cold " << c.registration_iterations
                          << "; mean error warm " << mean_error(first, b) << " cold "
                          << mean_error(first, c));
  CHECK(b.registration_iterations <= c.registration_iterations / 2);
  CHECK(mean_error(first, b) <= 0.005);
  CHECK(mean_error(first, b) <= mean_error(first, c) + 0.0005);
}

TEST_CASE("the warm start follows the prediction's motion", "[tracker][warm]") {
  // Between the cycles the sheet drops 6 cm, twice the warm gate, and the twin predicted that.
  const View before = view(0.9, 11), after = view(0.84, 21);
  SheetTracker tracker(config());
  REQUIRE(tracker.track(before.frames, prediction(0.9)).status == TrackStatus::kOk);
  const TrackResult r = tracker.track(after.frames, prediction(0.84));
  REQUIRE(r.status == TrackStatus::kOk);
  CHECK(r.registration_warm);
  CHECK_FALSE(r.registration_restarted);
  CHECK(mean_error(after, r) <= 0.005);
}

TEST_CASE("a sheet that moved beyond the warm gate is found again from the prediction",
          "[tracker][warm]") {
  // The sheet drops 8 cm and the prediction does not follow: the warm fit loses the sheet, and
  // the cycle fits again from the prediction (8-12 cm off) with the full gates.
  const View before = view(0.9, 11), after = view(0.82, 21);
  SheetTracker tracker(config());
  REQUIRE(tracker.track(before.frames, prediction(0.9)).status == TrackStatus::kOk);
  const TrackResult r = tracker.track(after.frames, prediction(0.9));
  REQUIRE(r.status == TrackStatus::kOk);
  CHECK(r.registration_warm);
  CHECK(r.registration_restarted);
  INFO("mean error " << mean_error(after, r));
  CHECK(mean_error(after, r) <= 0.005);
}

TEST_CASE("after a cycle that did not track, or on another mesh, the fit starts from the "
          "prediction",
          "[tracker][warm]") {
  const View v = view(0.9, 11);
  SheetTracker tracker(config());
  REQUIRE(tracker.track(v.frames, prediction(0.9)).status == TrackStatus::kOk);
  CHECK(tracker.track({}, prediction(0.9)).status == TrackStatus::kNoFrames);
  const TrackResult after_gap = tracker.track(v.frames, prediction(0.9));
  REQUIRE(after_gap.status == TrackStatus::kOk);
  CHECK_FALSE(after_gap.registration_warm);
  const TrackResult other_mesh = tracker.track(v.frames, prediction(0.9, 30, 26));
  REQUIRE(other_mesh.status == TrackStatus::kOk);
  CHECK_FALSE(other_mesh.registration_warm);
  tracker.forget_last_track();
  const TrackResult forgotten = tracker.track(v.frames, prediction(0.9, 30, 26));
  CHECK_FALSE(forgotten.registration_warm);
  const TrackResult next = tracker.track(v.frames, prediction(0.9, 30, 26));
  CHECK(next.registration_warm);
}

}  // namespace tracking
