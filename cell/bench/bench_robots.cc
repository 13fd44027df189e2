#include "cell/bench/bench_robots.h"

#include <algorithm>
#include <chrono>

#include "drivers/lcm_channels.h"
#include "sim_hw/world_start.h"

namespace cell_bench {

using Clock = std::chrono::steady_clock;

BenchRobots::BenchRobots(const sim_hw::WorldConfig& config, drivers::LcmBus& bus) : config_(config), bus_(bus) {
  // The same start as CellWorld's: arms at the IK solutions of the plan's hold positions, the
  // ply hanging from the grippers that have a grasp.
  const sim_hw::WorldStart start = sim_hw::plan_world_start(config_);
  sheet_ = std::make_unique<sim_hw::TrueSheet>(config_.sheet, config_.material, config_.truth);
  sheet_->load(start.grasps);
  for (const drivers::ArmConfig& arm : config_.hardware.arms)
    arms_.push_back(std::make_unique<sim_hw::SimulatedArm>(arm, start.arm_q.at(arm.name)));
  const sim_hw::GripperParameters parameters{config_.capture_distance_m, config_.grip_radius_m,
                                             config_.open_width_m};
  for (const drivers::GripperConfig& g : config_.hardware.grippers) {
    const sim_hw::SimulatedArm* arm = nullptr;
    for (const auto& a : arms_)
      if (a->name() == g.arm) arm = a.get();
    Eigen::Isometry3d manual = Eigen::Isometry3d::Identity();
    if (const auto it = start.manual_jaw_pose.find(g.name); it != start.manual_jaw_pose.end()) manual = it->second;
    const bool loaded = config_.plan.index_of(g.name) >= 0;
    grippers_.push_back(std::make_unique<sim_hw::SimulatedGripper>(g.name, arm, manual, *sheet_, parameters, loaded));
  }
  for (auto& arm : arms_) {
    sim_hw::SimulatedArm* a = arm.get();
    subscriptions_.push_back(bus_.subscribe<lcmt_iiwa_command>(
        drivers::channels::iiwa_command(a->name()), [this, a](const lcmt_iiwa_command& msg) {
          std::lock_guard lock(mutex_);
          a->command(msg);  // a malformed command is counted by the arm and not followed
        }));
  }
  for (auto& gripper : grippers_) {
    sim_hw::SimulatedGripper* g = gripper.get();
    subscriptions_.push_back(bus_.subscribe<prepreg_lcm::gripper_command_t>(
        drivers::channels::gripper_command(g->name()), [this, g](const prepreg_lcm::gripper_command_t& msg) {
          std::lock_guard lock(mutex_);
          g->command(msg);
        }));
  }
}

BenchRobots::~BenchRobots() {
  stop();
  for (const auto id : subscriptions_) bus_.unsubscribe(id);
}

void BenchRobots::start() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread([this] { run(); });
}

void BenchRobots::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

std::uint64_t BenchRobots::commands_accepted() const {
  std::lock_guard lock(mutex_);
  std::uint64_t n = 0;
  for (const auto& a : arms_) n += a->commands_accepted();
  return n;
}

void BenchRobots::run() {
  const double arm_dt_s = 1.0 / config_.arm_status_hz;
  const auto arm_period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(arm_dt_s));
  const auto gripper_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / config_.gripper_status_hz));
  auto next = Clock::now(), next_gripper = next;
  while (!stop_) {
    const std::int64_t utime = drivers::utime_now();
    const bool grippers_due = Clock::now() >= next_gripper;
    {
      std::lock_guard lock(mutex_);
      for (auto& arm : arms_) {
        arm->tick(arm_dt_s);
        bus_.publish(drivers::channels::iiwa_status(arm->name()), arm->status(utime));
      }
      for (auto& g : grippers_) {
        g->tick();  // a holding gripper carries its patch of the (unstepped) true sheet
        if (grippers_due) bus_.publish(drivers::channels::gripper_status(g->name()), g->status(utime));
      }
    }
    if (grippers_due) next_gripper = std::max(next_gripper + gripper_period, Clock::now());  // no burst after a stall
    next += arm_period;
    if (next < Clock::now()) next = Clock::now();  // late (busy cores): do not try to catch up
    std::this_thread::sleep_until(next);
  }
}

}  // namespace cell_bench
