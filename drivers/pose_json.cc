#include "drivers/pose_json.h"

#include <cmath>
#include <string>
#include <vector>

namespace drivers {
namespace {
constexpr double kQuaternionTolerance = 1e-3;  // |q| may differ from 1 by this much
}  // namespace

Eigen::Isometry3d parse_pose(const JsonField& f) {
  f.only_keys({"translation_m", "quaternion_wxyz", "rpy_deg"});
  const std::vector<double> t = f["translation_m"].numbers(3);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  const bool has_q = f.has("quaternion_wxyz"), has_rpy = f.has("rpy_deg");
  if (has_q == has_rpy) f.fail("must give exactly one of quaternion_wxyz [w, x, y, z] or rpy_deg [r, p, y]");
  if (has_q) {
    const std::vector<double> q = f["quaternion_wxyz"].numbers(4);
    Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
    if (std::abs(quat.norm() - 1.0) > kQuaternionTolerance)
      f["quaternion_wxyz"].fail("must be a unit quaternion (|q| = " + std::to_string(quat.norm()) + ")");
    pose.linear() = quat.normalized().toRotationMatrix();
  } else {
    const std::vector<double> rpy = f["rpy_deg"].numbers(3);
    const double k = M_PI / 180.0;
    pose.linear() = (Eigen::AngleAxisd(rpy[2] * k, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(rpy[1] * k, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(rpy[0] * k, Eigen::Vector3d::UnitX())).toRotationMatrix();
  }
  return pose;
}

}  // namespace drivers
