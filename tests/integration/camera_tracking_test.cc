// Issue 4 end to end: the twin's hanging sheet (truth) seen by three simulated D415s 1.2-1.8 m
// away, tracked by the real tracker from a prediction made with the wrong material. The tracked
// surface is compared with the true sheet, not with the cloud the tracker saw.
#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <numeric>

#include "sim_hw/sheet_scene.h"
#include "sim_hw/simulated_d415.h"
#include "tests/integration/hanging_sheet_scene.h"
#include "tracking/sheet_tracker.h"

namespace {

using integration::HangingSheet;

const HangingSheet& sheet() {
  static const HangingSheet s = integration::make_hanging_sheet(1500);
  return s;
}

sim_hw::SceneSource true_sheet_scene() {
  auto scene = std::make_shared<sim_hw::RenderScene>();
  scene->meshes.push_back(sim_hw::sheet_scene_mesh(sheet().mesh, sheet().truth_m));
  scene->floor = sim_hw::FloorPlane{};
  return [scene](double) { return std::shared_ptr<const sim_hw::RenderScene>(scene); };
}

tracking::TrackerConfig tracker_config() {
  tracking::TrackerConfig c;
  c.segmentation.box_min_m = {-1.0, -1.0, 0.3};  // above the floor, around the sheet
  c.segmentation.box_max_m = {1.0, 1.0, 1.3};
  return c;
}

struct Figures {
  double mean_m = 0, max_m = 0;
  int vertices = 0;
};

// Distance of the tracked vertices that the cameras saw to the true surface.
Figures tracked_surface_error(const tracking::TrackResult& r) {
  std::vector<Eigen::Vector3d> seen;
  for (std::size_t i = 0; i < r.vertices_m.size(); ++i) {
    if (r.vertex_observed[i]) seen.push_back(r.vertices_m[i]);
  }
  const std::vector<double> d = integration::distances_to_surface(seen, sheet().mesh, sheet().truth_m);
  Figures f;
  f.vertices = static_cast<int>(d.size());
  if (!d.empty()) {
    f.mean_m = std::accumulate(d.begin(), d.end(), 0.0) / d.size();
    f.max_m = *std::max_element(d.begin(), d.end());
  }
  return f;
}

// One frame from each camera that is alive (seeded from first_seed on, simulated clock).
std::vector<drivers::DepthFrame> capture(const std::vector<drivers::CameraConfig>& configs,
                                         const std::string& dead_camera = "", std::uint64_t first_seed = 11) {
  std::vector<drivers::DepthFrame> frames;
  std::uint64_t seed = first_seed;
  for (const auto& config : configs) {
    sim_hw::SimulatedD415Options options;
    options.scene = true_sheet_scene();
    options.seed = seed++;
    if (config.name == dead_camera) options.faults.dead_from_s = 0.0;
    sim_hw::SimulatedD415Camera camera(options);
    REQUIRE(camera.configure(config).ok);
    REQUIRE(camera.activate().ok);
    drivers::DepthFrame frame;
    const drivers::ReadStatus status = camera.read(frame);
    if (config.name == dead_camera) {
      CHECK(status == drivers::ReadStatus::kLost);
      continue;
    }
    REQUIRE(status == drivers::ReadStatus::kFrame);
    frames.push_back(std::move(frame));
  }
  return frames;
}

}  // namespace

TEST_CASE("three simulated D415s: the tracked sheet lies within 5 mm mean, 20 mm max of the truth",
          "[camera_tracking]") {
  const auto configs = integration::three_cameras(sheet().truth_m);
  for (const auto& c : configs) {
    const Eigen::Vector3d centre = sheet().truth_m.reshaped(3, sheet().truth_m.size() / 3).rowwise().mean();
    const double distance = (c.camera_to_cell.translation() - centre).norm();
    CHECK(distance >= 1.2);
    CHECK(distance <= 1.8);
  }
  // The prediction is visibly wrong before tracking (else the test would prove nothing).
  std::vector<Eigen::Vector3d> predicted;
  for (int i = 0; i < sheet().mesh.vertex_count(); ++i) predicted.push_back(twin::vertex(sheet().prediction_m, i));
  const auto before = integration::distances_to_surface(predicted, sheet().mesh, sheet().truth_m);
  const double before_max = *std::max_element(before.begin(), before.end());
  CHECK(before_max > 0.03);

  tracking::SheetTracker tracker(tracker_config());
  const tracking::TrackResult r =
      tracker.track(capture(configs), integration::to_surface_mesh(sheet().mesh, sheet().prediction_m));
  REQUIRE(r.status == tracking::TrackStatus::kOk);
  CHECK(r.cameras_used.size() == 3);
  const Figures f = tracked_surface_error(r);
  INFO("tracked-surface error: mean " << 1e3 * f.mean_m << " mm, max " << 1e3 * f.max_m << " mm over "
                                      << f.vertices << " seen vertices; prediction max "
                                      << 1e3 * before_max << " mm; coverage " << r.coverage.fraction);
  CHECK(f.mean_m <= 0.005);
  CHECK(f.max_m <= 0.020);
  CHECK(r.coverage.fraction > 0.8);
  // The prediction error the cell publishes sees the wrong material (against the predicted
  // surface, so the mesh's vertex spacing does not count as error).
  CHECK(r.prediction_error.surface_max_m > 0.03);
}

TEST_CASE("one simulated D415 dead: tracking continues from two and reports the lower coverage",
          "[camera_tracking]") {
  const auto configs = integration::three_cameras(sheet().truth_m);
  tracking::SheetTracker all(tracker_config()), two(tracker_config());
  const auto prediction = integration::to_surface_mesh(sheet().mesh, sheet().prediction_m);
  const tracking::TrackResult r3 = all.track(capture(configs), prediction);
  const tracking::TrackResult r2 = two.track(capture(configs, "cam_left"), prediction);
  REQUIRE(r3.status == tracking::TrackStatus::kOk);
  REQUIRE(r2.status == tracking::TrackStatus::kOk);
  CHECK(r2.cameras_used.size() == 2);
  // The coverage each cloud gives the TRUE sheet (same definition, on the true surface): what
  // the reported coverage must match. The three cameras overlap a lot; cam_left is the one whose
  // loss hides part of the sheet (true coverage 0.994 -> 0.983; losing cam_right hides nothing),
  // so the reported figure must drop with it.
  const tracking::SurfaceMesh truth = integration::to_surface_mesh(sheet().mesh, sheet().truth_m);
  const auto true_coverage = [&](const tracking::SheetTracker& t) {
    tracking::PointIndex cloud;
    cloud.build(t.last_resampled_cloud());
    return tracking::compute_coverage(truth.vertices_m, truth.triangles, cloud,
                                      tracker_config().coverage)
        .fraction;
  };
  const double truth3 = true_coverage(all), truth2 = true_coverage(two);
  CHECK(truth2 < truth3 - 0.005);
  CHECK(r3.coverage.fraction == Approx(truth3).margin(0.01));
  CHECK(r2.coverage.fraction == Approx(truth2).margin(0.01));
  CHECK(r2.coverage.fraction < r3.coverage.fraction);
  CHECK(r2.coverage.fraction > 0.3);
  const Figures f = tracked_surface_error(r2);
  INFO("two cameras: mean " << 1e3 * f.mean_m << " mm, max " << 1e3 * f.max_m << " mm, coverage "
                            << r2.coverage.fraction << " (three: " << r3.coverage.fraction
                            << "; of the true sheet: two " << truth2 << ", three " << truth3
                            << ")");
  CHECK(f.mean_m <= 0.005);
  CHECK(f.max_m <= 0.020);
}

namespace {

// Mean distance (m) of the seen tracked vertices from their own true positions: the prediction
// and the truth share the mesh, so vertex i is one material point in both.
double vertex_correspondence_error(const tracking::TrackResult& r) {
  double sum = 0.0;
  int seen = 0;
  for (std::size_t i = 0; i < r.vertices_m.size(); ++i) {
    if (!r.vertex_observed[i]) continue;
    sum += (r.vertices_m[i] - twin::vertex(sheet().truth_m, static_cast<int>(i))).norm();
    ++seen;
  }
  return sum / std::max(seen, 1);
}

}  // namespace

TEST_CASE("warm cycles track the true sheet as well as cold ones, in fewer iterations, without drift",
          "[camera_tracking]") {
  const auto configs = integration::three_cameras(sheet().truth_m);
  const auto prediction = integration::to_surface_mesh(sheet().mesh, sheet().prediction_m);
  tracking::TrackerConfig cold_config = tracker_config();
  cold_config.registration.warm_start = false;
  tracking::SheetTracker warm(tracker_config()), cold(cold_config);
  std::vector<double> warm_error, cold_error, warm_surface, cold_surface;
  constexpr int kCycles = 6;
  for (int cycle = 0; cycle < kCycles; ++cycle) {
    const auto frames = capture(configs, "", 11 + 10 * cycle);  // a new noise draw each cycle
    const tracking::TrackResult w = warm.track(frames, prediction);
    const tracking::TrackResult c = cold.track(frames, prediction);
    REQUIRE(w.status == tracking::TrackStatus::kOk);
    REQUIRE(c.status == tracking::TrackStatus::kOk);
    CHECK(w.registration_warm == (cycle > 0));
    CHECK_FALSE(w.registration_restarted);
    if (cycle > 0) CHECK(w.registration_iterations < c.registration_iterations);
    warm_error.push_back(vertex_correspondence_error(w));
    cold_error.push_back(vertex_correspondence_error(c));
    warm_surface.push_back(tracked_surface_error(w).mean_m);
    cold_surface.push_back(tracked_surface_error(c).mean_m);
  }
  const auto mean_after_first = [](const std::vector<double>& v) {
    return std::accumulate(v.begin() + 1, v.end(), 0.0) / (v.size() - 1);
  };
  INFO("vertex error warm " << 1e3 * mean_after_first(warm_error) << " mm (first " << 1e3 * warm_error.front()
                            << ", last " << 1e3 * warm_error.back() << "), cold " << 1e3 * mean_after_first(cold_error)
                            << " mm; surface warm " << 1e3 * mean_after_first(warm_surface) << ", cold "
                            << 1e3 * mean_after_first(cold_surface) << " mm");
  // As close to the true vertices and the true surface as the cold fits (within 0.3 mm), and
  // no drift along the sheet from cycle to cycle (carrying the whole last correction, not only
  // its normal part, drifted 3.8 -> 5.2 mm over 8 cycles here).
  CHECK(mean_after_first(warm_error) <= mean_after_first(cold_error) + 0.0003);
  CHECK(mean_after_first(warm_surface) <= mean_after_first(cold_surface) + 0.0003);
  CHECK(warm_error.back() <= warm_error.front() + 0.0003);
}
