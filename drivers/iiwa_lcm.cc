#include "drivers/iiwa_lcm.h"

#include <vector>

namespace drivers {
namespace {

std::vector<double> to_vector(const JointVector& q) {
  return std::vector<double>(q.data(), q.data() + q.size());
}

std::optional<JointVector> to_joint_vector(const std::vector<double>& values, int count) {
  if (count != kIiwaJoints || static_cast<int>(values.size()) != kIiwaJoints) return std::nullopt;
  const JointVector q = Eigen::Map<const JointVector>(values.data());
  if (!q.allFinite()) return std::nullopt;
  return q;
}

}  // namespace

lcmt_iiwa_command make_iiwa_command(std::int64_t utime, const JointVector& q_rad) {
  lcmt_iiwa_command msg;
  msg.utime = utime;
  msg.num_joints = kIiwaJoints;
  msg.joint_position = to_vector(q_rad);
  msg.num_torques = 0;
  return msg;
}

lcmt_iiwa_status make_iiwa_status(std::int64_t utime, const JointVector& measured_rad,
                                  const JointVector& velocity_rad_s,
                                  const JointVector& commanded_rad) {
  lcmt_iiwa_status msg;
  msg.utime = utime;
  msg.num_joints = kIiwaJoints;
  msg.joint_position_measured = to_vector(measured_rad);
  msg.joint_velocity_estimated = to_vector(velocity_rad_s);
  msg.joint_position_commanded = to_vector(commanded_rad);
  msg.joint_position_ipo = to_vector(commanded_rad);
  const std::vector<double> zero(kIiwaJoints, 0.0);
  msg.joint_torque_measured = zero;
  msg.joint_torque_commanded = zero;
  msg.joint_torque_external = zero;
  return msg;
}

std::optional<JointVector> commanded_positions(const lcmt_iiwa_command& msg) {
  if (msg.num_torques != 0) return std::nullopt;  // torque control is not used by this cell
  return to_joint_vector(msg.joint_position, msg.num_joints);
}

std::optional<JointVector> measured_positions(const lcmt_iiwa_status& msg) {
  return to_joint_vector(msg.joint_position_measured, msg.num_joints);
}

}  // namespace drivers
