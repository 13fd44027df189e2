// One tracker cycle: runs the stages in order and times them.
#include "tracking/sheet_tracker.h"

#include <algorithm>
#include <chrono>
#include <future>

#include <fmt/format.h>

#include "tracking/point_index.h"

namespace tracking {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point& start) {
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - start).count();
  start = now;
  return ms;
}

}  // namespace

const char* to_string(TrackStatus status) {
  switch (status) {
    case TrackStatus::kOk:
      return "ok";
    case TrackStatus::kNoFrames:
      return "no frames";
    case TrackStatus::kSheetNotSeen:
      return "sheet not seen";
    case TrackStatus::kBadPrediction:
      return "bad prediction";
    case TrackStatus::kRegistrationFailed:
      return "registration failed";
    case TrackStatus::kInternalError:
      return "internal error";
  }
  return "unknown";
}

SheetTracker::SheetTracker(TrackerConfig config) : config_(std::move(config)) {
  // The workspace box is applied while fusing (cheapest there); segmentation then counts it.
  FusionOptions fusion = config_.fusion;
  fusion.crop_to_box = true;
  fusion.box_min_m = config_.segmentation.box_min_m.cast<float>();
  fusion.box_max_m = config_.segmentation.box_max_m.cast<float>();
  fusion_.set_options(fusion);
  registration_.set_options(config_.registration);
}

TrackResult SheetTracker::track(const std::vector<drivers::DepthFrame>& frames,
                                const SurfaceMesh& prediction) {
  // The stages report bad data by status; what is left to throw is the libraries' own failures
  // (allocation), which the real-time caller must see as a failed cycle, not an exception.
  try {
    return run_cycle(frames, prediction);
  } catch (const std::exception& e) {
    TrackResult r;
    r.status = TrackStatus::kInternalError;
    r.message = e.what();
    r.vertices_m = prediction.vertices_m;
    return r;
  }
}

TrackResult SheetTracker::run_cycle(const std::vector<drivers::DepthFrame>& frames,
                                    const SurfaceMesh& prediction) {
  TrackResult r;
  const Clock::time_point cycle_start = Clock::now();
  Clock::time_point t = cycle_start;
  r.vertices_m = prediction.vertices_m;
  const auto finish = [&](TrackStatus status, std::string message) {
    if (status != TrackStatus::kOk) last_.valid = false;
    r.status = status;
    r.message = std::move(message);
    r.times.total_ms =
        std::chrono::duration<double, std::milli>(Clock::now() - cycle_start).count();
    return r;
  };
  if (std::string why = validate_mesh(prediction); !why.empty()) {
    return finish(TrackStatus::kBadPrediction, "prediction: " + why);
  }

  // Camera index = position in cameras_used, so calibration pairs name cameras that gave points.
  fused_.clear();
  for (const drivers::DepthFrame& frame : frames) {
    const int index = static_cast<int>(r.cameras_used.size());
    FrameReport report = fusion_.add_frame(frame, index, fused_);
    if (report.status == FrameStatus::kOk) r.cameras_used.push_back(frame.camera);
    r.frames.push_back(std::move(report));
  }
  int outside_box = 0;
  for (const FrameReport& report : r.frames) outside_box += report.outside_box;
  r.fused_points = static_cast<int>(fused_.size()) + outside_box;
  r.times.fusion_ms = ms_since(t);
  if (r.cameras_used.empty()) {
    return finish(TrackStatus::kNoFrames,
                  frames.empty() ? "no frame arrived" : "every frame was rejected");
  }

  sheet_ = segment_sheet(fused_, config_.segmentation, &r.segmentation);
  r.segmentation.input += outside_box;  // dropped by the fusion's crop, counted here as before
  r.segmentation.outside_box += outside_box;
  r.sheet_points = static_cast<int>(sheet_.size());
  r.times.segmentation_ms = ms_since(t);
  if (r.sheet_points < config_.min_sheet_points) {
    return finish(TrackStatus::kSheetNotSeen,
                  fmt::format("{} points passed segmentation, need {}", r.sheet_points,
                              config_.min_sheet_points));
  }

  resampled_ = resample_cloud(sheet_.points_m, config_.resample);
  r.resampled_points = static_cast<int>(resampled_.size());
  PointIndex cloud;
  cloud.build(resampled_);
  r.times.resample_ms = ms_since(t);

  // The prediction error against the observed points needs nothing the registration makes:
  // it runs on a second thread meanwhile (one search thread, beside the registration's).
  auto against_prediction = std::async(std::launch::async, [this, &prediction] {
    return observed_against_prediction(resampled_, prediction.vertices_m, prediction.triangles, 1);
  });
  RegistrationResult fit = register_prediction(prediction, cloud, r);
  r.times.registration_ms = ms_since(t);
  if (fit.status != RegistrationStatus::kOk) {
    return finish(TrackStatus::kRegistrationFailed, fit.message);
  }
  last_.valid = true;
  last_.triangles = prediction.triangles;
  last_.predicted_m = prediction.vertices_m;
  last_.tracked_m = fit.vertices_m;
  last_.matched_vertices = fit.matched_vertices;
  r.vertices_m = std::move(fit.vertices_m);
  r.vertex_observed = std::move(fit.observed);
  r.vertex_distance_to_cloud_m = std::move(fit.distance_to_cloud_m);

  r.coverage = compute_coverage(r.vertices_m, prediction.triangles, cloud, config_.coverage);
  r.times.coverage_ms = ms_since(t);
  r.prediction_error = against_prediction.get();
  add_vertex_error(r.prediction_error, prediction.vertices_m, r.vertices_m);
  r.times.prediction_error_ms = ms_since(t);
  // Only cycles that tracked count, so the first good cycle always checks.
  const int every = std::max(config_.calibration.every_n_cycles, 1);
  if (config_.calibration.enabled && cycle_++ % every == 0) {
    r.calibration =
        check_calibration(sheet_, static_cast<int>(r.cameras_used.size()), config_.calibration);
    r.calibration_checked = true;
  }
  r.times.calibration_ms = ms_since(t);
  return finish(TrackStatus::kOk, {});
}

RegistrationResult SheetTracker::register_prediction(const SurfaceMesh& prediction,
                                                     const PointIndex& cloud, TrackResult& r) {
  const RegistrationOptions& o = config_.registration;
  const std::size_t n = prediction.vertices_m.size();
  if (o.warm_start && last_.valid && last_.predicted_m.size() == n &&
      last_.triangles == prediction.triangles) {
    // The last track's correction of its prediction along the surface normal, carried onto
    // this prediction. Only the normal part: along the surface nothing but the seen border
    // places the sheet, and carrying the tangential part too let the vertices drift from their
    // material points cycle after cycle (the twin's hanging sheet seen by simulated D415s:
    // 3.8 -> 5.2 mm mean from the true vertices over 8 cycles, where this stays at 3.8-3.9 mm).
    const std::vector<Vec3> last_normal = vertex_normals(last_.predicted_m, prediction.triangles);
    const std::vector<Vec3> normal = vertex_normals(prediction.vertices_m, prediction.triangles);
    std::vector<Vec3> start(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double offset_m = last_normal[i].dot(last_.tracked_m[i] - last_.predicted_m[i]);
      start[i] = prediction.vertices_m[i] + offset_m * normal[i];
    }
    RegistrationResult warm = registration_.fit(prediction, cloud, &start);
    r.registration_warm = true;
    r.registration_iterations = warm.iterations;
    if (warm.status == RegistrationStatus::kOk &&
        warm.matched_vertices >= o.warm_min_matched_fraction * last_.matched_vertices) {
      return warm;
    }
    r.registration_restarted = true;
  }
  RegistrationResult cold = registration_.fit(prediction, cloud);
  r.registration_iterations += cold.iterations;
  return cold;
}

}  // namespace tracking
