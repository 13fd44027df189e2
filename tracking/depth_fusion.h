#pragma once
// Stage 1 of the tracker: one depth frame -> 3D points in the cell frame, each with its colour
// (looked up through depth_to_color and the colour intrinsics) and its source camera. Corrupt
// frames are rejected with a status; nothing on this path throws. DepthFrame::depth_mm is in
// millimetres by the driver interface (drivers apply CameraConfig::depth_unit_mm), so no unit here.

#include <string>
#include <vector>

#include "drivers/depth_camera.h"
#include "tracking/sensor_cloud.h"

namespace tracking {

struct FusionOptions {
  // Use every n-th pixel in each direction (like a RealSense decimation filter): 2 quarters the
  // points; at 848x480 and 1.5 m pixels are then ~4.6 mm apart, still 2-3 points per 8 mm voxel
  // from each camera. The benchmark measures 1 and 2.
  int pixel_stride = 2;
  double min_depth_m = 0.2;  // a D415 measures nothing closer; nearer values are artefacts
  double max_depth_m = 4.0;  // beyond the cell
  // Drop points outside this box (cell frame, m) while fusing, before their colour is looked up
  // and before they are copied: the segmentation's workspace box, applied where it is cheapest
  // (most pixels see the floor and the cell, not the sheet). The tracker sets it from
  // SegmentationOptions; off by default, so fusion on its own keeps every point.
  bool crop_to_box = false;
  Eigen::Vector3f box_min_m = Eigen::Vector3f::Constant(-1.0f);
  Eigen::Vector3f box_max_m = Eigen::Vector3f::Constant(1.0f);
};

enum class FrameStatus {
  kOk,
  kEmpty,          // no depth image or no valid pixel (all zero)
  kSizeMismatch,   // depth size != intrinsics width*height
  kBadIntrinsics,  // non-positive size or focal length, non-finite values
  kNonFinitePose,  // camera_to_cell or depth_to_color not finite (or not a rigid motion)
};
const char* to_string(FrameStatus status);

struct FrameReport {
  std::string camera;
  FrameStatus status = FrameStatus::kOk;
  std::string message;  // why rejected, or a note (colour ignored and why)
  int points = 0;       // points added
  int outside_box = 0;  // valid points dropped by crop_to_box
  bool color_used = false;
};

class DepthFusion {
 public:
  void set_options(const FusionOptions& options) { options_ = options; }
  const FusionOptions& options() const { return options_; }

  // Appends the frame's valid points to `cloud` with camera index `camera_index`. A rejected
  // frame adds nothing. Colour that does not fit its intrinsics is ignored (points get "no
  // colour") and the report says so, since depth alone is still useful.
  FrameReport add_frame(const drivers::DepthFrame& frame, int camera_index, SensorCloud& cloud);

 private:
  // Undistorted normalised ray (x/z, y/z) per pixel, cached per intrinsics: undistorting is an
  // iteration per pixel, and a camera's intrinsics do not change between frames.
  const std::vector<Eigen::Vector2f>& rays_for(const drivers::Intrinsics& in);

  FusionOptions options_;
  struct RayTable {
    drivers::Intrinsics intrinsics;
    std::vector<Eigen::Vector2f> rays;
  };
  std::vector<RayTable> ray_tables_;
  // Per-pixel scratch reused across frames (no allocation per cycle once warm).
  std::vector<Eigen::Vector3f> slot_points_;
  std::vector<std::uint8_t> slot_rgb_, slot_flags_;
};

// Checks shared with the tests: empty when usable, else why not.
std::string check_intrinsics(const drivers::Intrinsics& in);
std::string check_pose(const Eigen::Isometry3d& pose);

}  // namespace tracking
