#include "sim_hw/d415_model.h"

#include <cmath>
#include <numbers>

namespace sim_hw {

std::vector<drivers::StreamMode> d415_depth_modes() {
  return {{848, 480, 6},  {848, 480, 15},  {848, 480, 30}, {848, 480, 60},
          {1280, 720, 6}, {1280, 720, 15}, {1280, 720, 30}};
}

std::vector<drivers::StreamMode> d415_color_modes() { return d415_depth_modes(); }

bool is_d415_mode(const drivers::StreamMode& mode, const std::vector<drivers::StreamMode>& modes) {
  for (const auto& m : modes) {
    if (m.width == mode.width && m.height == mode.height && m.fps == mode.fps) return true;
  }
  return false;
}

drivers::Intrinsics pinhole_from_hfov(int width, int height, double hfov_deg) {
  drivers::Intrinsics k;
  k.width = width;
  k.height = height;
  const double half = 0.5 * hfov_deg * std::numbers::pi / 180.0;
  k.fx = 0.5 * width / std::tan(half);
  k.fy = k.fx;
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

drivers::Intrinsics d415_depth_intrinsics(const drivers::StreamMode& mode) {
  return pinhole_from_hfov(mode.width, mode.height, kD415DepthHfovDeg);
}

drivers::Intrinsics d415_color_intrinsics(const drivers::StreamMode& mode) {
  return pinhole_from_hfov(mode.width, mode.height, kD415ColorHfovDeg);
}

Eigen::Isometry3d d415_depth_to_color() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(kD415ColorOffsetM, 0.0, 0.0);
  return t;
}

Eigen::Isometry3d d415_right_in_depth() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(kD415BaselineM, 0.0, 0.0);
  return t;
}

}  // namespace sim_hw
