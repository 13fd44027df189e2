#pragma once
// Where the fake world starts: the ply loaded into the grippers as the grasp plan says. Each arm
// whose gripper has a grasp stands at the inverse-kinematics solution for the flange pose that
// puts its jaw at the grasp's hold position (grippers reach down, drivers::flange_pose_for_jaw);
// the other arms stand at home. The operator (MANUAL) holds its jaw at its hold position. Each
// patch is held flat (the sheet's placement orientation) at its hold position.

#include <map>
#include <string>
#include <vector>

#include "sim_hw/true_sheet.h"
#include "sim_hw/world_config.h"

namespace sim_hw {

struct WorldStart {
  std::map<std::string, drivers::JointVector> arm_q;        // per arm name, rad
  std::map<std::string, Eigen::Isometry3d> manual_jaw_pose;  // per arm-less gripper, cell frame
  std::vector<HeldGrasp> grasps;                             // the initial load
};

// Throws std::runtime_error naming the gripper (and its arm) when a hold position cannot be
// reached (the IK status and residual say how far off it stayed).
WorldStart plan_world_start(const WorldConfig& config);

}  // namespace sim_hw
