#pragma once
// The robots of a cell config file (JSON): arms and grippers, read by the cell controller and by
// the fake-hardware world, so both agree on where each arm stands and which gripper it carries.
// Other top-level keys of the file belong to other parts of the cell and are left alone.
//   "arms": [{"name": "LEFT", "model": "iiwa7",              (iiwa7 = R800, iiwa14 = R820)
//             "base_in_cell": {"translation_m": [...], "rpy_deg": [...]},   (see pose_json.h)
//             "tool_length_m": 0.15,     (flange -> jaw centre along the flange z axis, m)
//             "home_deg": [0, 30, 0, -90, 0, 60, 0]}, ...],  (optional, a7 values, deg)
//   "grippers": [{"name": "LEFT", "arm": "LEFT"},     (a gripper on an arm's flange)
//                {"name": "MANUAL"}]                  (no arm: held by the operator, who reads
//                                                      the hold position off the grasp plan)
// Names: letters, digits and '_' (they become LCM channel suffixes), unique; a gripper's arm must
// be listed; at most one gripper per arm. Errors throw std::invalid_argument naming the file and
// field.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "drivers/iiwa_kinematics.h"

namespace drivers {

struct ArmConfig {
  std::string name;
  IiwaModel model = IiwaModel::kIiwa7R800;
  Eigen::Isometry3d base_in_cell = Eigen::Isometry3d::Identity();
  double tool_length_m = 0.15;
  JointVector home_rad = JointVector::Zero();

  IiwaArm arm() const { return IiwaArm(iiwa_parameters(model), base_in_cell); }
};

struct GripperConfig {
  std::string name;
  std::string arm;  // empty: held by the operator (no arm)
};

struct CellHardwareConfig {
  std::vector<ArmConfig> arms;
  std::vector<GripperConfig> grippers;

  const ArmConfig* find_arm(const std::string& name) const;
  const GripperConfig* find_gripper(const std::string& name) const;
};

// Both keys optional (a tracker-only config has neither).
CellHardwareConfig parse_cell_hardware(const nlohmann::json& document, const std::string& source);
CellHardwareConfig read_cell_hardware(const std::string& path);

// Grippers reach down onto the sheet: the flange's z axis points down the cell's -z, its x axis
// along the cell's x turned by yaw_rad about the vertical. The jaw centre is tool_length_m along
// the flange z axis.
Eigen::Isometry3d flange_pose_for_jaw(const ArmConfig& arm, const Eigen::Vector3d& jaw_in_cell_m,
                                      double yaw_rad = 0.0);
Eigen::Vector3d jaw_position(const ArmConfig& arm, const Eigen::Isometry3d& flange_in_cell);

}  // namespace drivers
