#include "sim_hw/cell_world.h"

#include <algorithm>
#include <stdexcept>

#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_fault_t.hpp>

#include "drivers/lcm_channels.h"
#include "sim_hw/sheet_scene.h"
#include "sim_hw/world_start.h"

namespace sim_hw {

using Clock = std::chrono::steady_clock;

CellWorld::CellWorld(WorldConfig config, drivers::LcmBus& bus) : config_(std::move(config)), bus_(bus) {
  const WorldStart start = plan_world_start(config_);
  sheet_ = std::make_unique<TrueSheet>(config_.sheet, config_.material, config_.truth);
  load_report_ = sheet_->load(start.grasps);
  for (const drivers::ArmConfig& arm : config_.hardware.arms)
    arms_.push_back(std::make_unique<SimulatedArm>(arm, start.arm_q.at(arm.name)));
  const GripperParameters parameters{config_.capture_distance_m, config_.grip_radius_m, config_.open_width_m};
  for (const drivers::GripperConfig& g : config_.hardware.grippers) {
    const SimulatedArm* arm = nullptr;
    for (const auto& a : arms_)
      if (a->name() == g.arm) arm = a.get();
    Eigen::Isometry3d manual = Eigen::Isometry3d::Identity();
    if (const auto it = start.manual_jaw_pose.find(g.name); it != start.manual_jaw_pose.end()) manual = it->second;
    const bool loaded = config_.plan.index_of(g.name) >= 0;
    grippers_.push_back(std::make_unique<SimulatedGripper>(g.name, arm, manual, *sheet_, parameters, loaded));
  }
  sheet_mesh_ = sheet_scene_mesh(sheet_->mesh(), sheet_->positions());
  update_scene();
  for (const WorldCamera& cam : config_.cameras)
    cameras_.push_back(std::make_unique<EmulatedCameraRig>(cam, [this](double) { return scene(); }));
  subscribe();
  next_arm_tick_ = next_gripper_tick_ = Clock::now();
}

CellWorld::~CellWorld() {
  stop();
  for (const auto id : subscriptions_) bus_.unsubscribe(id);
}

void CellWorld::subscribe() {
  for (auto& arm : arms_) {
    SimulatedArm* a = arm.get();
    subscriptions_.push_back(bus_.subscribe<lcmt_iiwa_command>(drivers::channels::iiwa_command(a->name()), [this, a](const lcmt_iiwa_command& msg) {
      const bool ok = a->command(msg);
      std::lock_guard lock(counters_mutex_);
      ++(ok ? counters_.arm_commands : counters_.arm_commands_rejected);
    }));
  }
  for (auto& gripper : grippers_) {
    SimulatedGripper* g = gripper.get();
    subscriptions_.push_back(bus_.subscribe<prepreg_lcm::gripper_command_t>(
        drivers::channels::gripper_command(g->name()), [this, g](const prepreg_lcm::gripper_command_t& msg) {
          const bool ok = g->command(msg);
          std::lock_guard lock(counters_mutex_);
          ++(ok ? counters_.gripper_commands : counters_.gripper_commands_rejected);
        }));
  }
  subscriptions_.push_back(bus_.subscribe<prepreg_lcm::sim_fault_t>(
      std::string(drivers::channels::kSimFault),
      [this](const prepreg_lcm::sim_fault_t& msg) { on_fault(msg.target, msg.fault, msg.active); }));
}

void CellWorld::on_fault(const std::string& target, const std::string& fault, bool active) {
  bool ours = false, applied = false;
  for (auto& cam : cameras_)
    if (cam->name() == target) ours = true, applied = cam->apply_fault(fault, active);
  for (auto& arm : arms_)
    if (arm->name() == target) {
      ours = true;
      if (fault == "status_silent") arm->status_silent = active, applied = true;
    }
  std::lock_guard lock(counters_mutex_);
  if (!ours) ++counters_.faults_not_ours;  // e.g. "twin": the cell controller's
  else ++(applied ? counters_.faults_applied : counters_.faults_rejected);
}

void CellWorld::start() {
  if (physics_.joinable()) return;
  started_at_ = Clock::now();
  stop_physics_ = false;
  physics_ = std::thread([this] { physics_loop(); });
  for (auto& cam : cameras_) cam->start();
}

void CellWorld::stop() {
  for (auto& cam : cameras_) cam->stop();
  stop_physics_ = true;
  if (physics_.joinable()) physics_.join();
}

void CellWorld::physics_loop() {
  const auto dt = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config_.dt_s));
  const double truth_period_s = 1.0 / config_.truth_hz;
  double next_truth_s = 0.0;
  auto next = Clock::now();
  while (!stop_physics_) {
    sheet_->step(config_.dt_s);
    sim_time_s_ = sim_time_s_.load() + config_.dt_s;
    update_scene();
    if (sim_time_s_ >= next_truth_s) {
      publish_truth();
      next_truth_s += truth_period_s;
    }
    next += dt;
    const auto now = Clock::now();
    if (now > next + dt) {  // more than a step behind: do not try to catch up, run on from now
      next = now;
      std::lock_guard lock(counters_mutex_);
      ++counters_.physics_overruns;
    }
    std::this_thread::sleep_until(next);
  }
}

void CellWorld::update_scene() {
  update_sheet_vertices(sheet_mesh_, sheet_->positions());
  auto scene = std::make_shared<RenderScene>(config_.static_scene);
  scene->meshes.push_back(sheet_mesh_);
  std::lock_guard lock(scene_mutex_);
  scene_ = std::move(scene);
}

std::shared_ptr<const RenderScene> CellWorld::scene() const {
  std::lock_guard lock(scene_mutex_);
  return scene_;
}

void CellWorld::publish_truth() {
  const twin::VecX x = sheet_->positions();
  prepreg_lcm::sheet_state_t msg;
  msg.utime = drivers::utime_now();
  const int n = static_cast<int>(x.size() / 3);
  msg.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  msg.num_vertices = n;
  msg.x_m.resize(n), msg.y_m.resize(n), msg.z_m.resize(n);
  for (int i = 0; i < n; ++i) {
    msg.x_m[i] = static_cast<float>(x[3 * i]);
    msg.y_m[i] = static_cast<float>(x[3 * i + 1]);
    msg.z_m[i] = static_cast<float>(x[3 * i + 2]);
  }
  msg.num_observed_flags = 0;
  msg.coverage = 1.0f;
  std::lock_guard lock(counters_mutex_);
  msg.cycle_id = static_cast<std::int64_t>(counters_.truth_published);
  if (bus_.publish(std::string(drivers::channels::kSimTruth), msg)) ++counters_.truth_published;
}

void CellWorld::tick_devices(double dt_s, bool publish_grippers) {
  const std::int64_t utime = drivers::utime_now();
  for (auto& arm : arms_) {
    arm->tick(dt_s);
    if (!arm->status_silent) bus_.publish(drivers::channels::iiwa_status(arm->name()), arm->status(utime));
  }
  for (auto& g : grippers_) {
    g->tick();
    if (publish_grippers) bus_.publish(drivers::channels::gripper_status(g->name()), g->status(utime));
  }
}

void CellWorld::run_for(std::chrono::duration<double> duration, const std::atomic<bool>* stop) {
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(duration);
  const auto arm_period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / config_.arm_status_hz));
  const auto gripper_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / config_.gripper_status_hz));
  const double arm_dt_s = 1.0 / config_.arm_status_hz;
  while (Clock::now() < end && !(stop && stop->load())) {
    const auto now = Clock::now();
    if (now >= next_arm_tick_) {
      const bool grippers_due = now >= next_gripper_tick_;
      tick_devices(arm_dt_s, grippers_due);
      next_arm_tick_ = std::max(next_arm_tick_ + arm_period, now - arm_period);
      if (grippers_due) next_gripper_tick_ = std::max(next_gripper_tick_ + gripper_period, now - gripper_period);
    }
    const auto wait = std::clamp(next_arm_tick_ - Clock::now(), Clock::duration::zero(),
                                 std::chrono::duration_cast<Clock::duration>(std::chrono::milliseconds(5)));
    bus_.handle_for(std::chrono::ceil<std::chrono::milliseconds>(wait));  // never 0 ms: no busy wait
  }
}

std::string CellWorld::emulation_spec() const {
  std::string spec;
  for (const auto& cam : cameras_) {
    if (!spec.empty()) spec += ',';
    spec += cam->emulation_spec();
  }
  return spec;
}

WorldSnapshot CellWorld::snapshot() const {
  WorldSnapshot s;
  s.sim_time_s = sim_time_s_.load();
  s.wall_time_s = physics_.joinable() ? std::chrono::duration<double>(Clock::now() - started_at_).count() : 0.0;
  s.physics = sheet_->stats();
  s.sag_m = sheet_->sag_m();
  for (const auto& cam : cameras_) s.camera_frames.emplace_back(cam->name(), cam->frames());
  for (const auto& g : grippers_)
    if (g->holding()) s.holding.push_back(g->name());
  for (const auto& a : arms_)
    if (a->velocity().norm() > 1e-6) ++s.arms_moving;
  std::lock_guard lock(counters_mutex_);
  s.counters = counters_;
  return s;
}

}  // namespace sim_hw
