#include "sim_hw/simulated_gripper.h"

#include <cmath>

namespace sim_hw {

namespace {
constexpr double kPlyThicknessM = 0.0003;  // jaws closed on the ply stop this far apart
}

SimulatedGripper::SimulatedGripper(std::string name, const SimulatedArm* arm,
                                   const Eigen::Isometry3d& manual_jaw_pose, TrueSheet& sheet,
                                   GripperParameters parameters, bool closed)
    : name_(std::move(name)), arm_(arm), manual_jaw_pose_(manual_jaw_pose), sheet_(sheet),
      parameters_(parameters), closed_(closed), open_width_m_(parameters.open_width_m) {}

Eigen::Isometry3d SimulatedGripper::jaw_pose() const {
  return arm_ ? arm_->jaw_pose() : manual_jaw_pose_;
}

bool SimulatedGripper::command(const prepreg_lcm::gripper_command_t& msg) {
  using Cmd = prepreg_lcm::gripper_command_t;
  if (msg.action == Cmd::ACTION_CLOSE) {
    if (!closed_) sheet_.grip(name_, jaw_pose(), parameters_.capture_distance_m, parameters_.grip_radius_m);
    closed_ = true;
    return true;
  }
  if (msg.action == Cmd::ACTION_OPEN) {
    sheet_.release(name_);
    closed_ = false;
    if (std::isfinite(msg.width_m) && msg.width_m > 0) open_width_m_ = msg.width_m;
    return true;
  }
  ++rejected_;
  return false;
}

void SimulatedGripper::tick() {
  if (closed_) sheet_.move_jaw(name_, jaw_pose());
}

prepreg_lcm::gripper_status_t SimulatedGripper::status(std::int64_t utime) const {
  prepreg_lcm::gripper_status_t s;
  s.utime = utime;
  const bool holds = holding();
  s.state = closed_ ? prepreg_lcm::gripper_status_t::STATE_CLOSED : prepreg_lcm::gripper_status_t::STATE_OPEN;
  s.width_m = static_cast<float>(closed_ ? (holds ? kPlyThicknessM : 0.0) : open_width_m_);
  s.holding = holds;
  return s;
}

}  // namespace sim_hw
