#include "drivers/pose_json.h"

#include <cmath>
#include <string>
#include <vector>

namespace drivers {
namespace {
constexpr double kQuaternionTolerance = 1e-3;  // |q| may differ from 1 by this much
}  // namespace

Eigen::Isometry3d parse_pose(const JsonField& f) {
  f.only_keys({"translation_m", "quaternion_wxyz", "rpy_deg", "look_at_m"});
  const std::vector<double> t = f["translation_m"].numbers(3);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  const bool has_q = f.has("quaternion_wxyz"), has_rpy = f.has("rpy_deg"), has_look = f.has("look_at_m");
  if (int(has_q) + int(has_rpy) + int(has_look) != 1)
    f.fail("must give exactly one of quaternion_wxyz [w, x, y, z], rpy_deg [r, p, y] or look_at_m [x, y, z]");
  if (has_look) {
    // A camera's optical frame: z towards the target, x horizontal (z x up), y = z x x (down).
    const std::vector<double> a = f["look_at_m"].numbers(3);
    const Eigen::Vector3d z = (Eigen::Vector3d(a[0], a[1], a[2]) - pose.translation());
    if (z.norm() < 1e-6) f["look_at_m"].fail("must differ from translation_m");
    const Eigen::Vector3d zn = z.normalized();
    if (std::abs(zn.z()) > 0.999) f["look_at_m"].fail("must not be straight above or below translation_m (the image x axis would be undefined)");
    const Eigen::Vector3d x = zn.cross(Eigen::Vector3d::UnitZ()).normalized();
    pose.linear().col(0) = x;
    pose.linear().col(1) = zn.cross(x);
    pose.linear().col(2) = zn;
    return pose;
  }
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
