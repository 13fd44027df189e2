#pragma once
// The cell's side of the robots on the LCM bus: it receives IIWA_STATUS_<ARM> and
// GRIPPER_STATUS_<G> (malformed ones are dropped by the bus's checks or, for a status without
// seven finite joint positions, here, and counted, never acted on), knows where each gripper's
// jaw is (forward kinematics of the measured joints + the tool offset; a gripper without an arm
// is where the plan holds it), and sends IIWA_COMMAND_<ARM> toward each jaw target (inverse
// kinematics seeded from the last command, then drivers::limit_joint_command) and
// GRIPPER_COMMAND_<G>. Jaw targets move in a straight line at a bounded speed. Handling thread
// only (see LcmBus); never throws after construction.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/cell_hardware_config.h"
#include "drivers/lcm_bus.h"
#include "twin/trials/grasp_plan.h"

namespace cell {

struct ArmLink {
  drivers::ArmConfig config;
  std::optional<drivers::JointVector> measured_rad;
  std::int64_t last_status_host_us = 0;  // host steady clock (drivers::host_clock_us), 0: never
  std::uint64_t statuses = 0, malformed = 0;
  std::optional<drivers::JointVector> last_command_rad;
  std::uint64_t commands_sent = 0;
  std::string ik_problem;  // last IK that missed its target ("" when reached)
};

struct GripperLink {
  drivers::GripperConfig config;
  int arm = -1;                     // index into arms, -1: held by the operator
  twin::Vec3 target_m, goal_m;      // jaw target now, and where it is heading (cell frame)
  bool holding = true;              // last GRIPPER_STATUS (assumed holding until told)
  std::int64_t last_status_host_us = 0;
  std::uint64_t statuses = 0;
  std::uint64_t commands_sent = 0;
};

class RobotLink {
 public:
  // Subscribes the status channels of every arm and gripper. The jaw targets start at the plan's
  // hold positions (grippers not in the plan: at their measured position once known).
  RobotLink(drivers::LcmBus& bus, const drivers::CellHardwareConfig& hardware,
            const twin::GraspPlan& plan);
  ~RobotLink();
  RobotLink(const RobotLink&) = delete;
  RobotLink& operator=(const RobotLink&) = delete;

  // Jaw position of gripper g: FK of the arm's measured joints, or the target for an operator.
  std::optional<twin::Vec3> jaw_position(int g) const;
  // Arms whose status is older than timeout_ms (or never came), by name.
  std::vector<std::string> stale_arms(std::int64_t now_us, double timeout_ms) const;

  // Moves every jaw target toward its goal by at most speed_m_s * dt_s.
  void advance_targets(double dt_s, double speed_m_s);
  void set_goal(int g, const twin::Vec3& goal_m) { grippers_[g].goal_m = goal_m; }
  bool at_goal(int g) const { return (grippers_[g].goal_m - grippers_[g].target_m).norm() < 1e-6; }

  // IIWA_COMMAND_<ARM> for every arm with a known status: toward its gripper's jaw target (or
  // holding its last command), at most joint_speed_scale of the joint velocity limits.
  void command_arms(double dt_s, double joint_speed_scale);
  // GRIPPER_COMMAND_<G> open. Returns false when the bus refused it.
  bool open_gripper(int g);

  int arm_count() const { return static_cast<int>(arms_.size()); }
  int gripper_count() const { return static_cast<int>(grippers_.size()); }
  const ArmLink& arm(int a) const { return arms_[a]; }
  const GripperLink& gripper(int g) const { return grippers_[g]; }
  int gripper_index(const std::string& name) const;
  // Statuses dropped: by the bus (decode/check) on these subscriptions plus malformed joints.
  std::uint64_t dropped_statuses() const;

 private:
  drivers::LcmBus& bus_;
  std::vector<ArmLink> arms_;
  std::vector<GripperLink> grippers_;
  std::vector<drivers::LcmBus::SubscriptionId> subscriptions_;
};

}  // namespace cell
