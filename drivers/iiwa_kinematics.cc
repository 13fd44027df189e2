#include "drivers/iiwa_kinematics.h"

#include <cmath>
#include <stdexcept>

namespace drivers {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

JointVector degrees(std::array<double, kIiwaJoints> values_deg) {
  JointVector v;
  for (int i = 0; i < kIiwaJoints; ++i) v[i] = values_deg[i] * kDegToRad;
  return v;
}

// Joint axis directions in the joint's own (pre-rotation) frame: A1 z, A2 y, A3 z, A4 -y, ...
const std::array<Eigen::Vector3d, kIiwaJoints>& local_axes() {
  static const std::array<Eigen::Vector3d, kIiwaJoints> axes = {
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(),  Eigen::Vector3d::UnitZ(),
      -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(),
      Eigen::Vector3d::UnitZ()};
  return axes;
}

}  // namespace

const char* to_string(IiwaModel model) {
  return model == IiwaModel::kIiwa7R800 ? "iiwa7" : "iiwa14";
}

IiwaModel iiwa_model_from_string(const std::string& text) {
  if (text == "iiwa7" || text == "R800") return IiwaModel::kIiwa7R800;
  if (text == "iiwa14" || text == "R820") return IiwaModel::kIiwa14R820;
  throw std::invalid_argument("unknown iiwa model '" + text +
                              "', expected iiwa7 (R800) or iiwa14 (R820)");
}

IiwaParameters iiwa_parameters(IiwaModel model) {
  IiwaParameters p;
  p.model = model;
  p.position_max_rad = degrees({170, 120, 170, 120, 170, 120, 175});
  p.position_min_rad = -p.position_max_rad;
  if (model == IiwaModel::kIiwa7R800) {
    p.d1_m = 0.34;
    p.d3_m = 0.40;
    p.d5_m = 0.40;
    p.d7_m = 0.126;
    p.velocity_max_rad_s = degrees({98, 98, 100, 130, 140, 180, 180});
  } else {
    p.d1_m = 0.36;
    p.d3_m = 0.42;
    p.d5_m = 0.40;
    p.d7_m = 0.126;
    p.velocity_max_rad_s = degrees({85, 85, 100, 75, 130, 135, 135});
  }
  return p;
}

IiwaArm::IiwaArm(IiwaParameters parameters, const Eigen::Isometry3d& base_in_cell)
    : parameters_(std::move(parameters)), base_in_cell_(base_in_cell) {}

IiwaArm::Frames IiwaArm::frames(const JointVector& q) const {
  // Distance travelled along the link after each joint, before the next one.
  const std::array<double, kIiwaJoints> link_after = {
      parameters_.d1_m, 0.0, parameters_.d3_m, 0.0, parameters_.d5_m, 0.0, parameters_.d7_m};
  Frames f;
  Eigen::Isometry3d t = base_in_cell_;
  for (int i = 0; i < kIiwaJoints; ++i) {
    const Eigen::Vector3d& axis = local_axes()[i];
    f.origin[i] = t.translation();
    f.axis[i] = t.linear() * axis;
    t.rotate(Eigen::AngleAxisd(q[i], axis));
    t.translate(Eigen::Vector3d(0, 0, link_after[i]));
  }
  f.flange = t;
  return f;
}

Eigen::Isometry3d IiwaArm::flange_in_cell(const JointVector& q) const { return frames(q).flange; }

IiwaJacobian IiwaArm::jacobian(const JointVector& q) const {
  const Frames f = frames(q);
  const Eigen::Vector3d tip = f.flange.translation();
  IiwaJacobian j;
  for (int i = 0; i < kIiwaJoints; ++i) {
    j.block<3, 1>(0, i) = f.axis[i].cross(tip - f.origin[i]);
    j.block<3, 1>(3, i) = f.axis[i];
  }
  return j;
}

bool IiwaArm::within_limits(const JointVector& q, double tolerance_rad) const {
  return (q.array() >= parameters_.position_min_rad.array() - tolerance_rad).all() &&
         (q.array() <= parameters_.position_max_rad.array() + tolerance_rad).all();
}

JointVector IiwaArm::clamp_to_limits(const JointVector& q) const {
  return q.cwiseMax(parameters_.position_min_rad).cwiseMin(parameters_.position_max_rad);
}

}  // namespace drivers
