// The whole tracker cycle against a sagging sheet seen by three noisy cameras: registration
// recovers the true shape from a perturbed prediction, coverage and prediction error are
// reported, a missing camera degrades coverage but not tracking, bad input gives a status.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "tests/tracking/analytic_scene.h"
#include "tracking/sheet_tracker.h"

namespace tracking {
namespace {

using testing::SheetShape;

SheetShape true_shape() {
  SheetShape s;
  s.sag_m = 0.12;
  s.slope_x = 0.04;
  s.ripple_m = 0.015;
  return s;
}

// The twin's prediction: same sheet, less sag, no tilt or ripple (up to ~5 cm off).
SheetShape predicted_shape() {
  SheetShape s;
  s.sag_m = 0.085;
  return s;
}

struct World {
  std::shared_ptr<const testing::SaggingSheet> sheet;
  std::vector<drivers::DepthFrame> frames;  // three cameras, 848x480, D415 noise
  SurfaceMesh prediction;
};

const World& world() {
  static const World w = [] {
    World w;
    const testing::Scene scene = testing::sheet_scene(true_shape(), &w.sheet);
    const auto cameras = testing::three_cameras(848, 480);
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      w.frames.push_back(testing::render_frame(
          scene, cameras[c], testing::NoiseModel{0.0015, static_cast<std::uint32_t>(11 + c)}));
    }
    w.prediction = testing::SaggingSheet(predicted_shape(), {0, 0, 0}).mesh(40, 34);
    return w;
  }();
  return w;
}

TrackerConfig test_config() {
  TrackerConfig c;
  c.segmentation.box_min_m = Vec3(-0.9, -0.8, 0.5);
  c.segmentation.box_max_m = Vec3(0.9, 0.8, 1.3);
  return c;
}

struct SurfaceError {
  double mean_m = 0, max_m = 0;
  int vertices = 0;
};

SurfaceError error_vs_truth(const World& w, const std::vector<Vec3>& vertices,
                            const std::vector<std::uint8_t>* only = nullptr) {
  SurfaceError e;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (only && !(*only)[i]) continue;
    const double d = w.sheet->distance(vertices[i]);
    e.mean_m += d;
    e.max_m = std::max(e.max_m, d);
    ++e.vertices;
  }
  e.mean_m /= std::max(e.vertices, 1);
  return e;
}

}  // namespace

TEST_CASE("tracking recovers the sagging sheet from a perturbed prediction", "[tracker]") {
  const World& w = world();
  const SurfaceError before = error_vs_truth(w, w.prediction.vertices_m);
  SheetTracker tracker(test_config());
  const TrackResult r = tracker.track(w.frames, w.prediction);
  REQUIRE(r.status == TrackStatus::kOk);
  CHECK(r.cameras_used == std::vector<std::string>{"cam_front", "cam_right", "cam_left"});
  const SurfaceError after = error_vs_truth(w, r.vertices_m);
  INFO("prediction mean " << before.mean_m << " max " << before.max_m << "; tracked mean "
                          << after.mean_m << " max " << after.max_m << " iterations "
                          << r.registration_iterations << " coverage " << r.coverage.fraction);
  CHECK(before.mean_m > 0.015);  // the prediction really is off (up to 4 cm)
  CHECK(before.max_m > 0.035);
  CHECK(after.mean_m <= 0.005);
  CHECK(after.max_m <= 0.020);
  CHECK(r.coverage.fraction > 0.98);
  int observed = 0;
  for (std::uint8_t o : r.vertex_observed) observed += o;
  CHECK(observed > 0.95 * r.vertices_m.size());
  CHECK(r.times.total_ms > 0.0);
}

TEST_CASE("prediction error: Algorithm 1 figures and tracked minus predicted per vertex",
          "[tracker]") {
  const World& w = world();
  SheetTracker tracker(test_config());
  const TrackResult off = tracker.track(w.frames, w.prediction);
  const SurfaceMesh truth_mesh = w.sheet->mesh(40, 34);
  const TrackResult right = tracker.track(w.frames, truth_mesh);
  REQUIRE(off.status == TrackStatus::kOk);
  REQUIRE(right.status == TrackStatus::kOk);
  const PredictionError& e = off.prediction_error;
  CHECK(e.points == off.resampled_points);
  CHECK(e.score_m == Approx(e.mean_m + 0.5 * e.max_m));
  // A right prediction leaves only the distance from each point to its nearest vertex (vertices
  // 3 cm apart, so up to ~2 cm); the wrong one adds its offset (up to 4 cm).
  CHECK(right.prediction_error.max_m < 0.025);
  CHECK(e.mean_m > right.prediction_error.mean_m + 0.005);
  CHECK(e.max_m > right.prediction_error.max_m + 0.01);
  // Against the predicted surface the right prediction leaves only noise and the mesh's chords
  // (a few mm), far below its vertex figure; the wrong one still shows its offset.
  CHECK(right.prediction_error.surface_mean_m < 0.004);
  CHECK(right.prediction_error.surface_mean_m < 0.5 * right.prediction_error.mean_m);
  CHECK(e.surface_max_m > right.prediction_error.surface_max_m + 0.01);
  CHECK(e.surface_mean_m <= e.mean_m);
  // Per vertex, tracked minus predicted is the true correction: vertical here, since the two
  // shapes differ in height over the same footprint.
  double mismatch = 0.0;
  for (std::size_t i = 0; i < w.prediction.vertices_m.size(); ++i) {
    const Vec3& p = w.prediction.vertices_m[i];
    const double true_dz = truth_mesh.vertices_m[i].z() - p.z();
    mismatch += std::abs(e.per_vertex_m[i].z() - true_dz);
    CHECK(e.per_vertex_norm_m[i] == Approx(e.per_vertex_m[i].norm()));
  }
  CHECK(mismatch / w.prediction.vertices_m.size() < 0.005);
}

TEST_CASE("one camera missing: tracking continues with lower coverage", "[tracker]") {
  const World& w = world();
  SheetTracker tracker(test_config());
  const TrackResult all = tracker.track(w.frames, w.prediction);
  REQUIRE(all.status == TrackStatus::kOk);
  for (std::size_t missing = 0; missing < 3; ++missing) {
    std::vector<drivers::DepthFrame> two;
    for (std::size_t c = 0; c < 3; ++c) {
      if (c != missing) two.push_back(w.frames[c]);
    }
    const TrackResult r = tracker.track(two, w.prediction);
    REQUIRE(r.status == TrackStatus::kOk);
    CHECK(r.cameras_used.size() == 2);
    CHECK(r.coverage.fraction < all.coverage.fraction - 0.02);
    CHECK(r.coverage.fraction > 0.85);
    // Where the two cameras saw the sheet, it is tracked as well as with three.
    const SurfaceError seen = error_vs_truth(w, r.vertices_m, &r.coverage.covered);
    INFO("camera " << missing << " missing: coverage " << r.coverage.fraction << " mean "
                   << seen.mean_m << " max " << seen.max_m);
    CHECK(seen.mean_m <= 0.005);
    CHECK(seen.max_m <= 0.020);
  }
}

TEST_CASE("bad cycles end with a status, never an exception", "[tracker]") {
  const World& w = world();
  SheetTracker tracker(test_config());
  SECTION("no frame arrived") {
    const TrackResult r = tracker.track({}, w.prediction);
    CHECK(r.status == TrackStatus::kNoFrames);
    CHECK(r.vertices_m == w.prediction.vertices_m);  // the prediction stands in
  }
  SECTION("every frame corrupt") {
    std::vector<drivers::DepthFrame> frames = w.frames;
    frames[0].depth_mm.resize(10);
    frames[1].camera_to_cell.translation().z() = std::numeric_limits<double>::quiet_NaN();
    std::fill(frames[2].depth_mm.begin(), frames[2].depth_mm.end(), 0);
    const TrackResult r = tracker.track(frames, w.prediction);
    CHECK(r.status == TrackStatus::kNoFrames);
    REQUIRE(r.frames.size() == 3);
    CHECK(r.frames[0].status == FrameStatus::kSizeMismatch);
    CHECK(r.frames[1].status == FrameStatus::kNonFinitePose);
    CHECK(r.frames[2].status == FrameStatus::kEmpty);
  }
  SECTION("one corrupt frame among good ones") {
    std::vector<drivers::DepthFrame> frames = w.frames;
    frames[1].depth_intrinsics.fx = std::numeric_limits<double>::quiet_NaN();
    const TrackResult r = tracker.track(frames, w.prediction);
    CHECK(r.status == TrackStatus::kOk);
    CHECK(r.frames[1].status == FrameStatus::kBadIntrinsics);
    CHECK(r.cameras_used == std::vector<std::string>{"cam_front", "cam_left"});
  }
  SECTION("the sheet is outside the workspace box") {
    TrackerConfig c = test_config();
    c.segmentation.box_min_m.z() = 1.2;
    SheetTracker high(c);
    const TrackResult r = high.track(w.frames, w.prediction);
    CHECK(r.status == TrackStatus::kSheetNotSeen);
    CHECK_FALSE(r.message.empty());
  }
  SECTION("the prediction is not a mesh") {
    SurfaceMesh bad = w.prediction;
    bad.vertices_m[5].x() = std::numeric_limits<double>::infinity();
    CHECK(tracker.track(w.frames, bad).status == TrackStatus::kBadPrediction);
    bad = w.prediction;
    bad.triangles[3][1] = 100000;
    const TrackResult r = tracker.track(w.frames, bad);
    CHECK(r.status == TrackStatus::kBadPrediction);
    CHECK(r.message.find("triangle 3") != std::string::npos);
  }
}

}  // namespace tracking
