#include "cell/robot_link.h"

#include "drivers/depth_camera.h"
#include "drivers/iiwa_inverse_kinematics.h"
#include "drivers/iiwa_lcm.h"
#include "drivers/joint_command_limiter.h"
#include "drivers/lcm_channels.h"

namespace cell {

RobotLink::RobotLink(drivers::LcmBus& bus, const drivers::CellHardwareConfig& hardware,
                     const twin::GraspPlan& plan)
    : bus_(bus) {
  for (const auto& a : hardware.arms) arms_.push_back(ArmLink{a, {}, 0, 0, 0, {}, 0, {}});
  for (const auto& g : hardware.grippers) {
    GripperLink link;
    link.config = g;
    for (std::size_t a = 0; a < arms_.size(); ++a) {
      if (arms_[a].config.name == g.arm) link.arm = static_cast<int>(a);
    }
    const int k = plan.index_of(g.name);
    link.target_m = link.goal_m = k >= 0 ? plan.grasps[k].hold_position_m : twin::Vec3::Zero();
    grippers_.push_back(link);
  }
  for (std::size_t a = 0; a < arms_.size(); ++a) {
    subscriptions_.push_back(bus_.subscribe<lcmt_iiwa_status>(
        drivers::channels::iiwa_status(arms_[a].config.name), [this, a](const lcmt_iiwa_status& msg) {
          ArmLink& arm = arms_[a];
          const auto q = drivers::measured_positions(msg);
          if (!q) {  // fewer than 7 joints or non-finite: never acted on
            ++arm.malformed;
            return;
          }
          arm.measured_rad = *q;
          arm.last_status_host_us = drivers::host_clock_us();
          ++arm.statuses;
        }));
  }
  for (std::size_t g = 0; g < grippers_.size(); ++g) {
    subscriptions_.push_back(bus_.subscribe<prepreg_lcm::gripper_status_t>(
        drivers::channels::gripper_status(grippers_[g].config.name),
        [this, g](const prepreg_lcm::gripper_status_t& msg) {
          grippers_[g].holding = msg.holding;
          grippers_[g].last_status_host_us = drivers::host_clock_us();
          ++grippers_[g].statuses;
        }));
  }
}

RobotLink::~RobotLink() {
  for (auto id : subscriptions_) bus_.unsubscribe(id);
}

int RobotLink::gripper_index(const std::string& name) const {
  for (std::size_t g = 0; g < grippers_.size(); ++g) {
    if (grippers_[g].config.name == name) return static_cast<int>(g);
  }
  return -1;
}

std::optional<twin::Vec3> RobotLink::jaw_position(int g) const {
  const GripperLink& link = grippers_[g];
  if (link.arm < 0) return link.target_m;
  const ArmLink& arm = arms_[link.arm];
  if (!arm.measured_rad) return std::nullopt;
  return drivers::jaw_position(arm.config, arm.config.arm().flange_in_cell(*arm.measured_rad));
}

std::vector<std::string> RobotLink::stale_arms(std::int64_t now_us, double timeout_ms) const {
  std::vector<std::string> out;
  for (const auto& a : arms_) {
    if (a.last_status_host_us == 0 || (now_us - a.last_status_host_us) > timeout_ms * 1000.0) {
      out.push_back(a.config.name);
    }
  }
  return out;
}

void RobotLink::advance_targets(double dt_s, double speed_m_s) {
  const double step = speed_m_s * dt_s;
  for (auto& g : grippers_) {
    const twin::Vec3 d = g.goal_m - g.target_m;
    g.target_m = d.norm() <= step ? g.goal_m : twin::Vec3(g.target_m + d.normalized() * step);
  }
}

void RobotLink::command_arms(double dt_s, double joint_speed_scale) {
  for (auto& arm : arms_) {
    if (!arm.measured_rad) continue;  // nothing to seed from: never command blind
    if (!arm.last_command_rad) arm.last_command_rad = *arm.measured_rad;
    drivers::JointVector target = *arm.last_command_rad;  // hold unless a gripper needs moving
    for (const auto& g : grippers_) {
      if (g.arm < 0 || arms_[g.arm].config.name != arm.config.name) continue;
      const drivers::IiwaArm model = arm.config.arm();
      const auto ik = drivers::solve_inverse_kinematics(
          model, drivers::flange_pose_for_jaw(arm.config, g.target_m), *arm.last_command_rad);
      if (ik.status == drivers::IkStatus::kConverged) {
        target = ik.q;
        arm.ik_problem.clear();
      } else {
        arm.ik_problem = std::string("IK ") + drivers::to_string(ik.status);
      }
    }
    const drivers::LimitedCommand c = drivers::limit_joint_command(
        arm.config.arm().parameters(), *arm.last_command_rad, target, dt_s, joint_speed_scale);
    if (bus_.publish(drivers::channels::iiwa_command(arm.config.name),
                     drivers::make_iiwa_command(drivers::utime_now(), c.q))) {
      arm.last_command_rad = c.q;
      ++arm.commands_sent;
    }
  }
}

bool RobotLink::open_gripper(int g) {
  prepreg_lcm::gripper_command_t cmd{};
  cmd.utime = drivers::utime_now();
  cmd.action = prepreg_lcm::gripper_command_t::ACTION_OPEN;
  cmd.width_m = 0.08f;  // fully open: the ply falls free of the jaws
  cmd.force_n = 0.0f;
  const bool ok = bus_.publish(drivers::channels::gripper_command(grippers_[g].config.name), cmd);
  if (ok) ++grippers_[g].commands_sent;
  return ok;
}

std::uint64_t RobotLink::dropped_statuses() const {
  std::uint64_t n = 0;
  for (const auto& a : arms_) n += a.malformed;
  for (auto id : subscriptions_) {
    const drivers::BusCounters c = bus_.counters(id);
    n += c.decode_failures + c.rejected;
  }
  return n;
}

}  // namespace cell
