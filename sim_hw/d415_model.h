#pragma once
// The geometry of a RealSense D415 as the simulation models it: the stream modes it offers, the
// pinhole intrinsics that follow from its fields of view, its stereo baseline and where its
// colour imager sits relative to the depth (left IR) imager. Figures are nominal datasheet values
// (depth ~65 deg, colour ~69 deg horizontal field of view, 55 mm baseline, colour ~15 mm from the
// left imager); a real unit's calibration differs slightly and is passed in CameraConfig.

#include <vector>

#include <Eigen/Geometry>

#include "drivers/depth_camera.h"

namespace sim_hw {

inline constexpr double kD415DepthHfovDeg = 65.0;
inline constexpr double kD415ColorHfovDeg = 69.0;
inline constexpr double kD415BaselineM = 0.055;       // right IR imager at +x in the depth frame
inline constexpr double kD415ColorOffsetM = 0.015;    // depth -> colour translation along x
inline constexpr double kD415MinRangeM = 0.3;
inline constexpr double kD415MaxRangeM = 10.0;

// The depth (or colour) modes the simulated D415 accepts: 848x480 at 6/15/30/60 fps and
// 1280x720 at 6/15/30 fps (the USB 3 modes of a real D415 that the cell uses).
std::vector<drivers::StreamMode> d415_depth_modes();
std::vector<drivers::StreamMode> d415_color_modes();
bool is_d415_mode(const drivers::StreamMode& mode, const std::vector<drivers::StreamMode>& modes);

// Square-pixel pinhole intrinsics with the given horizontal field of view (deg), no distortion.
// Pixel (c, r) has its centre at (u, v) = (c, r), so the principal point is the image centre
// ((W-1)/2, (H-1)/2).
drivers::Intrinsics pinhole_from_hfov(int width, int height, double hfov_deg);

drivers::Intrinsics d415_depth_intrinsics(const drivers::StreamMode& mode);
drivers::Intrinsics d415_color_intrinsics(const drivers::StreamMode& mode);

// Maps points from the depth frame to the colour frame (as librealsense's depth->color
// extrinsics): p_color = p_depth + (0.015, 0, 0) m, i.e. the colour imager sits 15 mm to the
// left (-x) of the left IR imager, axes parallel.
Eigen::Isometry3d d415_depth_to_color();

// Pose of the right IR imager in the depth (left IR) frame: +x by the baseline.
Eigen::Isometry3d d415_right_in_depth();

}  // namespace sim_hw
