#pragma once
// Kinematic model of the KUKA LBR iiwa 7 R800 and iiwa 14 R820 arms: joint limits, forward
// kinematics to the flange and the geometric Jacobian, with the arm's base placed in the cell.
//
// Chain (joint axes at the zero configuration, arm straight up along the base z axis; the sign
// conventions of Drake's iiwa models, RobotLocomotion/drake
// manipulation/models/iiwa_description/iiwa7/iiwa7_no_collision.sdf, which follow the robot's):
//   A1 about +z at the base, A2 about +y at height d1, A3 about +z, A4 about -y at d1 + d3,
//   A5 about +z, A6 about +y at d1 + d3 + d5, A7 about +z; the flange at d1 + d3 + d5 + d7 with
//   the base's orientation.
// Link lengths (m), the standard DH values (e.g. gonzafernan/iiwa_matlab iiwa_init.m for the
// R800; GiorgioMedico/AntiSloshing create_lbr.m for both):
//   R800: d1 0.34, d3 0.40, d5 0.40, d7 0.126;  R820: d1 0.36, d3 0.42, d5 0.40, d7 0.126.
// Position limits (deg, both models): A1..A7 = +-170, 120, 170, 120, 170, 120, 175.
// Velocity limits (deg/s): R800 98, 98, 100, 130, 140, 180, 180 (lbr-stack/lbr_fri_ros2_stack
//   lbr_description/urdf/iiwa7/joint_limits.yaml); R820 85, 85, 100, 75, 130, 135, 135 (Drake's
//   iiwa_description/README.md, from KUKA's LBR iiwa brochure).

#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace drivers {

inline constexpr int kIiwaJoints = 7;
using JointVector = Eigen::Matrix<double, kIiwaJoints, 1>;  // A1..A7, rad (or rad/s)
using IiwaJacobian = Eigen::Matrix<double, 6, kIiwaJoints>;   // rows: v (m/s), w (rad/s)

enum class IiwaModel { kIiwa7R800, kIiwa14R820 };
const char* to_string(IiwaModel model);
// "iiwa7" / "iiwa14" (also "R800" / "R820"); throws std::invalid_argument naming the text.
IiwaModel iiwa_model_from_string(const std::string& text);

struct IiwaParameters {
  IiwaModel model = IiwaModel::kIiwa7R800;
  double d1_m = 0, d3_m = 0, d5_m = 0, d7_m = 0;  // base->A2, A2->A4, A4->A6, A6->flange
  JointVector position_min_rad;
  JointVector position_max_rad;
  JointVector velocity_max_rad_s;
};

// The data-sheet parameters of a model.
IiwaParameters iiwa_parameters(IiwaModel model);

class IiwaArm {
 public:
  // base_in_cell: the pose of the arm's base frame (A1 axis = its z axis, z up from the mounting
  // flange) in the cell frame.
  explicit IiwaArm(IiwaParameters parameters,
                   const Eigen::Isometry3d& base_in_cell = Eigen::Isometry3d::Identity());

  const IiwaParameters& parameters() const { return parameters_; }
  const Eigen::Isometry3d& base_in_cell() const { return base_in_cell_; }

  // Flange pose in the cell frame.
  Eigen::Isometry3d flange_in_cell(const JointVector& q) const;
  // Geometric Jacobian of the flange origin in the cell frame (rows 0-2 linear, 3-5 angular).
  IiwaJacobian jacobian(const JointVector& q) const;

  // True when every joint is within its position limits (plus tolerance_rad).
  bool within_limits(const JointVector& q, double tolerance_rad = 0) const;
  JointVector clamp_to_limits(const JointVector& q) const;
  // Longest distance from the A2 axis to the flange (arm straight), m.
  double reach_m() const { return parameters_.d3_m + parameters_.d5_m + parameters_.d7_m; }

 private:
  // Joint origins and axes in the cell frame plus the flange pose, for one configuration.
  struct Frames {
    std::array<Eigen::Vector3d, kIiwaJoints> origin;
    std::array<Eigen::Vector3d, kIiwaJoints> axis;
    Eigen::Isometry3d flange;
  };
  Frames frames(const JointVector& q) const;

  IiwaParameters parameters_;
  Eigen::Isometry3d base_in_cell_;
};

}  // namespace drivers
