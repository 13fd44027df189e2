#include "sim_hw/cell_world.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <stdexcept>

#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_fault_t.hpp>

#include "drivers/lcm_channels.h"
#include "sim_hw/sheet_scene.h"
#include "sim_hw/world_start.h"

namespace sim_hw {

using Clock = std::chrono::steady_clock;

namespace {

// The k-th event of a periodic kind, in whole microseconds since the start.
std::int64_t event_us(std::int64_t k, double period_s) { return std::llround(static_cast<double>(k) * period_s * 1e6); }

}  // namespace

CellWorld::CellWorld(WorldConfig config, drivers::LcmBus& bus, WorldClockOptions clock)
    : config_(std::move(config)), bus_(bus) {
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
  clock_ = std::make_unique<WorldClock>(std::move(clock), bus_);
  subscribe();
  serve_due_events();  // time 0: the first statuses and frames
  clock_->publish(false);
}

CellWorld::~CellWorld() {
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
    if (cam->name() == target) ours = true, applied = cam->apply_fault(fault, active, clock_->sim_s());
  for (auto& arm : arms_)
    if (arm->name() == target) {
      ours = true;
      if (fault == "status_silent") arm->status_silent = active, applied = true;
    }
  std::lock_guard lock(counters_mutex_);
  if (!ours) ++counters_.faults_not_ours;  // e.g. "twin": the cell controller's
  else ++(applied ? counters_.faults_applied : counters_.faults_rejected);
}

void CellWorld::drain_bus() {
  while (bus_.handle_for(std::chrono::milliseconds(0)).messages > 0) {
  }
}

std::int64_t CellWorld::next_event_us() const {
  std::int64_t next = std::min({event_us(arm_ticks_, 1.0 / config_.arm_status_hz),
                                event_us(physics_steps_, config_.dt_s), event_us(truths_, 1.0 / config_.truth_hz)});
  for (const auto& cam : cameras_) next = std::min(next, cam->next_frame_us());
  return next;
}

void CellWorld::serve_due_events() {
  const std::int64_t now = clock_->sim_us();
  // The arms and grippers first (they carry the jaws the sheet follows), then the sheet, the
  // truth, and the frames of the sheet as it now is.
  const double arm_dt_s = 1.0 / config_.arm_status_hz;
  while (event_us(arm_ticks_, arm_dt_s) <= now) {
    const bool grippers_due = event_us(gripper_ticks_, 1.0 / config_.gripper_status_hz) <= event_us(arm_ticks_, arm_dt_s);
    tick_devices(arm_dt_s, grippers_due);
    ++arm_ticks_;
    if (grippers_due) ++gripper_ticks_;
  }
  bool stepped = false;
  while (event_us(physics_steps_, config_.dt_s) <= now) {
    if (physics_steps_ > 0) sheet_->step(config_.dt_s);  // step 0 is the loaded sheet at time 0
    ++physics_steps_;
    stepped = true;
  }
  if (stepped) update_scene();
  while (event_us(truths_, 1.0 / config_.truth_hz) <= now) {
    publish_truth();
    ++truths_;
  }
  std::vector<std::future<void>> renders;
  for (auto& cam : cameras_)
    if (cam->next_frame_us() <= now) renders.push_back(std::async(std::launch::async, [&cam] { cam->serve_frame(); }));
  for (auto& r : renders) r.get();
}

bool CellWorld::turn(std::int64_t until_us, const std::atomic<bool>* stop) {
  drain_bus();
  const std::int64_t target = std::min({next_event_us(), clock_->limit_us(), until_us});
  if (target <= clock_->sim_us()) return false;
  if (!clock_->pace_to(target, stop)) return false;
  drain_bus();  // what arrived while pacing acts at the new time, as it would have on the wall
  clock_->advance_to(target);
  serve_due_events();
  clock_->publish(false);
  return true;
}

void CellWorld::run_for(std::chrono::duration<double> duration, const std::atomic<bool>* stop) {
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(duration);
  while (Clock::now() < end && !(stop && stop->load())) {
    if (!turn(WorldClock::kUnlimited, stop)) clock_->wait_held(std::chrono::milliseconds(5));
  }
}

bool CellWorld::run_until(double sim_s, std::chrono::duration<double> patience, const std::atomic<bool>* stop) {
  const std::int64_t until = std::llround(sim_s * 1e6);
  auto held_since = Clock::now();
  while (clock_->sim_us() < until) {
    if (stop && stop->load()) return false;
    if (turn(until, stop)) {
      held_since = Clock::now();
    } else {
      if (Clock::now() - held_since > patience) return false;
      clock_->wait_held(std::chrono::milliseconds(5));
    }
  }
  return true;
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
  s.sim_time_s = clock_->sim_s();
  s.real_time_factor = clock_->real_time_factor();
  s.held_by = clock_->held_by();
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
