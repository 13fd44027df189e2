#pragma once
// Keeps a joint position command within what the arm can do: the target is clamped to the
// position limits, then the step from the current command to it is shortened so no joint moves
// faster than its velocity limit over dt. Used by the cell before publishing lcmt_iiwa_command
// and by the simulated arm when following one.

#include "drivers/iiwa_kinematics.h"

namespace drivers {

struct LimitedCommand {
  JointVector q;                 // the command to send, rad
  bool position_clamped = false; // the target was outside the position limits
  bool velocity_clamped = false; // the step was shortened to respect the velocity limits
};

// current: the last commanded (or measured) configuration, rad; target: where the caller wants
// to go, rad; dt_s: time until the next command, s (> 0). velocity_scale (0, 1] slows all joints
// alike (e.g. 0.5 for half speed). The step keeps its direction (all joints are scaled by the
// same factor), so the flange follows the same joint-space line as the unlimited command.
// A non-finite target or dt <= 0 returns current unchanged with both flags set.
LimitedCommand limit_joint_command(const IiwaParameters& parameters, const JointVector& current,
                                   const JointVector& target, double dt_s,
                                   double velocity_scale = 1.0);

}  // namespace drivers
