#include "sim_hw/world_start.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "drivers/iiwa_inverse_kinematics.h"

namespace sim_hw {

WorldStart plan_world_start(const WorldConfig& config) {
  WorldStart start;
  for (const drivers::ArmConfig& arm : config.hardware.arms) start.arm_q[arm.name] = arm.home_rad;
  const Eigen::Matrix3d patch_rotation = config.sheet.placement.rotation;
  for (const drivers::GripperConfig& gripper : config.hardware.grippers) {
    const int index = config.plan.index_of(gripper.name);
    Eigen::Isometry3d jaw = Eigen::Isometry3d::Identity();
    if (gripper.arm.empty()) {
      if (index < 0) continue;  // the operator holds nothing
      jaw.translation() = config.plan.grasps[index].hold_position_m;
      start.manual_jaw_pose[gripper.name] = jaw;
    } else {
      if (index < 0) continue;  // this arm stays at home with its gripper open
      const drivers::ArmConfig& arm = *config.hardware.find_arm(gripper.arm);
      const twin::Vec3 hold = config.plan.grasps[index].hold_position_m;
      drivers::IkOptions options;
      options.restarts = 40;  // start-up only: try hard, the answer is repeatable
      const drivers::IkResult ik = drivers::solve_inverse_kinematics(
          arm.arm(), drivers::flange_pose_for_jaw(arm, hold), arm.home_rad, options);
      if (ik.status != drivers::IkStatus::kConverged) {
        std::ostringstream why;
        why << "gripper " << gripper.name << " (arm " << arm.name << ", " << drivers::to_string(arm.model)
            << "): the hold position [" << hold.transpose() << "] m of " << config.plan_path
            << " is not reachable: " << drivers::to_string(ik.status) << ", flange "
            << ik.position_residual_m * 1000 << " mm / " << ik.orientation_residual_rad * 180 / M_PI
            << " deg off";
        throw std::runtime_error(why.str());
      }
      start.arm_q[arm.name] = ik.q;
      jaw = arm.arm().flange_in_cell(ik.q);
      jaw.translation() = drivers::jaw_position(arm, jaw);
    }
    HeldGrasp held;
    held.clamp = config.plan.grasps[index].clamp;
    held.clamp.id = gripper.name;
    held.patch_pose.linear() = patch_rotation;
    held.patch_pose.translation() = config.plan.grasps[index].hold_position_m;
    held.jaw_pose = jaw;
    start.grasps.push_back(held);
  }
  return start;
}

}  // namespace sim_hw
