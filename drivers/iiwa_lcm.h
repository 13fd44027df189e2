#pragma once
// Conversions between the iiwa LCM messages (Drake-compatible lcmt_iiwa_command /
// lcmt_iiwa_status) and joint vectors, so the cell and the simulated arms fill and read them the
// same way a real iiwa LCM driver does: seven joints, position control, no torques.

#include <cstdint>
#include <optional>

#include <lcmt_iiwa_command.hpp>
#include <lcmt_iiwa_status.hpp>

#include "drivers/iiwa_kinematics.h"

namespace drivers {

// A position-control command: num_joints = 7, num_torques = 0.
lcmt_iiwa_command make_iiwa_command(std::int64_t utime, const JointVector& q_rad);

// A status as a driver reports it; torques 0 (the simulated arms do not model them), the
// interpolator position equal to the commanded one.
lcmt_iiwa_status make_iiwa_status(std::int64_t utime, const JointVector& measured_rad,
                                  const JointVector& velocity_rad_s,
                                  const JointVector& commanded_rad);

// The commanded positions, or nothing when the message is not a 7-joint position command or
// holds a non-finite value (such a command must be dropped, never acted on).
std::optional<JointVector> commanded_positions(const lcmt_iiwa_command& msg);
// The measured positions, or nothing when the status does not have 7 finite joint positions.
std::optional<JointVector> measured_positions(const lcmt_iiwa_status& msg);

}  // namespace drivers
