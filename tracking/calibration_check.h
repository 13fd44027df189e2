#pragma once
// Stage 6 of the tracker: do the cameras agree? Where two cameras see the same part of the
// sheet, each point of one camera's cloud should lie on the surface the other camera saw. A bad
// extrinsic (camera_to_cell) shifts or tilts one camera's cloud, which shows as a point-to-plane
// distance well above the depth noise. For each point of camera a (voxel-averaged) the local
// plane of camera b is fitted to b's points within a radius (PCL mean and covariance: the same
// estimate NormalEstimation makes), and the distance to it taken; median and 90th percentile
// over the overlap are compared with thresholds.

#include <string>
#include <vector>

#include "tracking/sensor_cloud.h"

namespace tracking {

struct CalibrationCheckOptions {
  bool enabled = true;
  // A camera knocked out of calibration stays so; checking twice a second at 30 Hz is enough and
  // keeps the check (as costly as a third of a cycle) out of most cycles.
  int every_n_cycles = 15;
  double voxel_m = 0.01;         // per-camera averaging before the comparison
  double plane_radius_m = 0.02;  // neighbourhood of camera b that defines the plane at a point
  int min_plane_points = 6;
  int min_overlap_points = 50;  // fewer common points: the pair is not judged
  int max_points = 1500;        // points of camera a used per pair (evenly subsampled)
  // Flag above these. Agreeing D415s at 1.2-1.8 m (stride 2, 1 cm voxels) give a median of about
  // 1 mm and a 90th percentile of about 3 mm; one camera 1 cm or 1 degree off gives 3-15 mm
  // and 6.5-16 mm (tests/tracking/calibration_check_test.cc).
  double max_median_m = 0.0025;
  double max_p90_m = 0.006;
};

struct CameraPairAgreement {
  int camera_a = 0, camera_b = 0;  // indices into the cycle's camera list
  int overlap_points = 0;
  bool judged = false;                 // enough overlap to say anything
  double median_m = 0.0, p90_m = 0.0;  // absolute point-to-plane distance
  bool flagged = false;
};

// `cloud` holds points of several cameras (SensorCloud::camera); `cameras` is the number of
// camera indices. Pairs are (a, b) with a < b.
std::vector<CameraPairAgreement> check_calibration(const SensorCloud& cloud, int cameras,
                                                   const CalibrationCheckOptions& options);

}  // namespace tracking
