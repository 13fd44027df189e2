#pragma once
// One simulated KUKA LBR iiwa (7 R800 or 14 R820, from the cell config) in position control, as
// an iiwa LCM driver presents it: it follows the latest lcmt_iiwa_command within the joint
// position and velocity limits (drivers::limit_joint_command, once per status tick) and reports
// lcmt_iiwa_status every tick. A malformed command (not 7 joints, torques sent, non-finite) is
// counted and never acted on. Not thread-safe: one thread (the world's LCM thread) owns it.

#include <cstdint>
#include <string>

#include <lcmt_iiwa_command.hpp>
#include <lcmt_iiwa_status.hpp>

#include "drivers/cell_hardware_config.h"

namespace sim_hw {

class SimulatedArm {
 public:
  // q_start: where the arm stands at start-up (rad, within limits).
  SimulatedArm(drivers::ArmConfig config, const drivers::JointVector& q_start);

  const drivers::ArmConfig& config() const { return config_; }
  const std::string& name() const { return config_.name; }

  // Takes a command as the new target; false (and counted) when it is malformed.
  bool command(const lcmt_iiwa_command& msg);
  // Advances dt_s (s) towards the target within the limits.
  void tick(double dt_s);
  lcmt_iiwa_status status(std::int64_t utime) const;

  const drivers::JointVector& q() const { return q_; }
  const drivers::JointVector& velocity() const { return qd_; }
  const drivers::JointVector& target() const { return target_; }
  Eigen::Isometry3d flange_in_cell() const { return arm_.flange_in_cell(q_); }
  // The jaw pose (position = jaw centre, rotation = the flange's), cell frame.
  Eigen::Isometry3d jaw_pose() const;

  std::uint64_t commands_accepted() const { return accepted_; }
  std::uint64_t commands_rejected() const { return rejected_; }
  bool limited() const { return limited_; }  // the last tick was clamped by a limit

  // Fault injection: a silent arm publishes no status (the world skips it).
  bool status_silent = false;

 private:
  drivers::ArmConfig config_;
  drivers::IiwaArm arm_;
  drivers::JointVector q_, qd_, target_;
  std::uint64_t accepted_ = 0, rejected_ = 0;
  bool limited_ = false;
};

}  // namespace sim_hw
