#include "sim_hw/simulated_arm.h"

#include "drivers/iiwa_lcm.h"
#include "drivers/joint_command_limiter.h"

namespace sim_hw {

SimulatedArm::SimulatedArm(drivers::ArmConfig config, const drivers::JointVector& q_start)
    : config_(std::move(config)), arm_(config_.arm()), q_(arm_.clamp_to_limits(q_start)),
      qd_(drivers::JointVector::Zero()), target_(q_) {}

bool SimulatedArm::command(const lcmt_iiwa_command& msg) {
  const std::optional<drivers::JointVector> q = drivers::commanded_positions(msg);
  if (!q) {
    ++rejected_;
    return false;
  }
  target_ = *q;
  ++accepted_;
  return true;
}

void SimulatedArm::tick(double dt_s) {
  if (!(dt_s > 0)) return;
  const drivers::LimitedCommand next = drivers::limit_joint_command(arm_.parameters(), q_, target_, dt_s);
  limited_ = next.position_clamped || next.velocity_clamped;
  qd_ = (next.q - q_) / dt_s;
  q_ = next.q;
}

lcmt_iiwa_status SimulatedArm::status(std::int64_t utime) const {
  return drivers::make_iiwa_status(utime, q_, qd_, target_);
}

Eigen::Isometry3d SimulatedArm::jaw_pose() const {
  Eigen::Isometry3d jaw = flange_in_cell();
  jaw.translation() = drivers::jaw_position(config_, jaw);
  return jaw;
}

}  // namespace sim_hw
