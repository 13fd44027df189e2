#pragma once
// One simulated gripper of the cell config: on an arm's flange (the jaw follows the arm) or held
// by the operator stand-in (MANUAL: the jaw stays at the plan's hold position for it). CLOSE
// grips the true sheet if it is within the capture distance of the jaw (holding), else closes on
// nothing; OPEN lets go. A holding gripper carries its patch as the jaw moves (tick()).
// One thread (the world's LCM thread) owns it; the sheet is thread-safe.

#include <cstdint>
#include <string>

#include <prepreg_lcm/gripper_command_t.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>

#include "sim_hw/simulated_arm.h"
#include "sim_hw/true_sheet.h"

namespace sim_hw {

struct GripperParameters {
  double capture_distance_m = 0.03;
  double grip_radius_m = 0.02;
  double open_width_m = 0.06;
};

class SimulatedGripper {
 public:
  // arm: the arm carrying it, or nullptr for the operator, who holds the jaw at manual_jaw_pose.
  // closed: the gripper starts closed (holding when the sheet was loaded into it).
  SimulatedGripper(std::string name, const SimulatedArm* arm, const Eigen::Isometry3d& manual_jaw_pose,
                   TrueSheet& sheet, GripperParameters parameters, bool closed);

  const std::string& name() const { return name_; }
  bool manual() const { return arm_ == nullptr; }
  Eigen::Isometry3d jaw_pose() const;

  // Acts on a command; false (and counted) for an unknown action.
  bool command(const prepreg_lcm::gripper_command_t& msg);
  // The jaw moved with its arm: the held patch follows.
  void tick();
  prepreg_lcm::gripper_status_t status(std::int64_t utime) const;

  bool closed() const { return closed_; }
  bool holding() const { return sheet_.holding(name_); }
  std::uint64_t commands_rejected() const { return rejected_; }

 private:
  std::string name_;
  const SimulatedArm* arm_;
  Eigen::Isometry3d manual_jaw_pose_;
  TrueSheet& sheet_;
  GripperParameters parameters_;
  bool closed_ = false;
  double open_width_m_;
  std::uint64_t rejected_ = 0;
};

}  // namespace sim_hw
