#pragma once
// The real-time sheet tracker: one call per cycle turns the depth frames that arrived (any
// subset of the cameras; a dead camera is simply missing) and the twin's predicted mesh into
// the observed surface, its coverage, the prediction error and a calibration check.
//
//   frames -> fusion (cell-frame points, colour, camera) -> segmentation (box, colour)
//          -> voxel resampling -> registration of the prediction -> coverage, prediction error
//          -> calibration check between cameras
//
// The cyclic path never throws: corrupt frames are rejected per frame, and the result's status
// says whether the cycle produced a tracked surface. Not thread-safe: one tracker per thread (it
// keeps buffers and the registration's factorisation between cycles).

#include <string>
#include <vector>

#include "drivers/depth_camera.h"
#include "tracking/calibration_check.h"
#include "tracking/cloud_resampling.h"
#include "tracking/depth_fusion.h"
#include "tracking/sheet_segmentation.h"
#include "tracking/surface_metrics.h"
#include "tracking/surface_registration.h"

namespace tracking {

struct TrackerConfig {
  FusionOptions fusion;
  SegmentationOptions segmentation;
  ResampleOptions resample;
  RegistrationOptions registration;
  CoverageOptions coverage;
  CalibrationCheckOptions calibration;
  int min_sheet_points = 200;  // fewer segmented points: the sheet was not seen this cycle
};

enum class TrackStatus {
  kOk,
  kNoFrames,       // no frame arrived, or every frame was rejected
  kSheetNotSeen,   // frames were fine but too few points passed segmentation
  kBadPrediction,  // the predicted mesh is unusable (see message)
  kRegistrationFailed,
  kInternalError,  // a library threw (out of memory, ...); the message says what
};
const char* to_string(TrackStatus status);

// Wall-clock milliseconds per stage of the cycle. The prediction error against the observed
// points runs beside the registration; prediction_error_ms is what is left of it after.
struct StageTimes {
  double fusion_ms = 0, segmentation_ms = 0, resample_ms = 0, registration_ms = 0;
  double coverage_ms = 0, prediction_error_ms = 0, calibration_ms = 0, total_ms = 0;
};

struct TrackResult {
  TrackStatus status = TrackStatus::kOk;
  std::string message;
  std::vector<FrameReport> frames;        // one per input frame, in input order
  std::vector<std::string> cameras_used;  // names of the frames that contributed points
  // Observed surface: the prediction's vertices moved onto the cloud (prediction when not ok).
  std::vector<Vec3> vertices_m;
  std::vector<std::uint8_t> vertex_observed;       // a cloud point within observed_distance
  std::vector<double> vertex_distance_to_cloud_m;  // NaN when none near
  Coverage coverage;
  PredictionError prediction_error;
  bool calibration_checked = false;              // this cycle ran the calibration check
  std::vector<CameraPairAgreement> calibration;  // indices into cameras_used
  SegmentationCounts segmentation;
  int fused_points = 0, sheet_points = 0, resampled_points = 0;
  int registration_iterations = 0;
  // The registration started from the last cycle's tracked surface (registration.warm_start);
  // `registration_restarted`: that warm fit lost too many matches and the cycle's result is a
  // second fit from the prediction (its iterations are in registration_iterations too).
  bool registration_warm = false;
  bool registration_restarted = false;
  StageTimes times;
};

class SheetTracker {
 public:
  explicit SheetTracker(TrackerConfig config = {});
  const TrackerConfig& config() const { return config_; }

  // One cycle. Never throws: whatever goes wrong ends in the result's status. Successive calls
  // are successive cycles: a cycle that tracked lets the next one start its registration from
  // its result (registration.warm_start); a cycle that did not, or a prediction on another
  // mesh, makes the next one start from the prediction.
  TrackResult track(const std::vector<drivers::DepthFrame>& frames, const SurfaceMesh& prediction);
  // The next cycle starts from the prediction (after a pause, say, or a sheet swapped).
  void forget_last_track() { last_.valid = false; }

  const SensorCloud& last_sheet_cloud() const { return sheet_; }  // for display and debugging
  const std::vector<Eigen::Vector3f>& last_resampled_cloud() const { return resampled_; }

 private:
  TrackResult run_cycle(const std::vector<drivers::DepthFrame>& frames,
                        const SurfaceMesh& prediction);
  // The registration of this cycle: warm from the last track when it can, else (or when the
  // warm fit lost the sheet) from the prediction. Fills the result's registration fields.
  RegistrationResult register_prediction(const SurfaceMesh& prediction, const PointIndex& cloud,
                                         TrackResult& r);

  // The last cycle that tracked: its prediction and result on that prediction's mesh.
  struct LastTrack {
    bool valid = false;
    std::vector<Eigen::Vector3i> triangles;
    std::vector<Vec3> predicted_m, tracked_m;
    int matched_vertices = 0;
  };

  TrackerConfig config_;
  DepthFusion fusion_;
  SurfaceRegistration registration_;
  SensorCloud fused_, sheet_;  // reused across cycles
  std::vector<Eigen::Vector3f> resampled_;
  LastTrack last_;
  long cycle_ = 0;
};

}  // namespace tracking
