#include "tests/cell/cell_rig.h"

#include <prepreg_lcm/sim_clock_t.hpp>

#include <fstream>

#include "cell/cell_twin.h"
#include "drivers/camera_registry.h"
#include "drivers/cell_hardware_config.h"
#include "drivers/iiwa_inverse_kinematics.h"
#include "drivers/iiwa_lcm.h"
#include "drivers/lcm_channels.h"
#include "sim_hw/sheet_scene.h"
#include "twin/trials/grasp_plan.h"
#include "twin/model/material.h"

namespace cell_test {
namespace {

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in.good());
  return nlohmann::json::parse(in);
}

}  // namespace

RigFiles default_files() {
  const std::string examples = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/";
  RigFiles f;
  f.config = read_json(examples + "fake_cell.json");
  f.material = read_json(examples + "composite_identified.json");
  f.plan = read_json(examples + "four_grasp_plan.json");
  // Start-up waits for every camera's first frame and every arm's first status: here about
  // 0.1 s and 10 ms. The limits are far above that (a busy machine or a sanitizer build is
  // slower, and a healthy rig must not fail to start); the start-up tests of a missing camera
  // or arm set their own, shorter ones.
  f.config["cell"] = {{"lcm_url", "memq://"}, {"clock", "sim"}, {"cycle_hz", 15}, {"min_cameras", 2},
                      {"robot_status_timeout_ms", 250}, {"camera_stale_ms", 500},
                      {"startup_timeout_s", 60}, {"camera_startup_timeout_s", 15},
                      {"arm_status_timeout_s", 5}};
  f.config["twin"] = {{"material_file", "material.json"},
                      {"sheet", {{"width_m", 1.17}, {"height_m", 0.975}, {"target_triangles", 800}}}};
  f.config["job"] = {{"plan_file", "plan.json"}};
  // Settled states are recorded; calibrations (minutes of background fitting) only where a test
  // asks for them.
  f.config["learning"] = {{"calibrate", false}, {"diagnose", false}};
  for (auto& c : f.config["cameras"]) {
    c["backend"] = "test_sim";
    c["uri"] = "";  // the scene comes from the rig, not a file
  }
  return f;
}

std::string write_files(const testing_support::TempDir& dir, const RigFiles& files) {
  testing_support::write_file(dir / "material.json", files.material.dump(2));
  testing_support::write_file(dir / "plan.json", files.plan.dump(2));
  testing_support::write_file(dir / "cell.json", files.config.dump(2));
  return (dir / "cell.json").string();
}

namespace {
SimCameras* g_current = nullptr;  // the registry's factory is global; one rig at a time
}

SimCameras::SimCameras(const cell::CellConfig& config)
    : clock_(config.cell.clock == drivers::ClockSource::kSim ? sim_hw::SimClock::kProcess : sim_hw::SimClock::kWall) {
  // The truth: the plan's ply at its own static equilibrium (the cell's twin finds the same one
  // from the same start, so the prediction error is the tracker's and the mesh's, not the model's).
  const twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
  cell::CellTwin truth(config.sheet.mesh, twin::read_material_file(config.material_file), plan,
                       cell::placement_under_grasps(plan));
  std::vector<twin::Vec3> holds;
  for (const auto& g : plan.grasps) holds.push_back(g.hold_position_m);
  REQUIRE(truth.initialise(holds).empty());
  auto scene = std::make_shared<sim_hw::RenderScene>();
  scene->meshes.push_back(sim_hw::sheet_scene_mesh(truth.mesh(), truth.positions()));
  scene->floor = sim_hw::FloorPlane{};
  scene_ = scene;
  g_current = this;
  drivers::register_depth_camera_backend("test_sim", [] {
    sim_hw::SimulatedD415Options o;
    auto s = g_current->scene_;
    o.scene = [s](double) { return s; };
    o.clock = g_current->clock_;
    o.seed = 100 + g_current->cameras_.size();
    auto cam = std::make_unique<sim_hw::SimulatedD415Camera>(o);
    const int index = static_cast<int>(g_current->cameras_.size());
    g_current->cameras_.push_back(cam.get());
    for (int dead : g_current->dead_from_start_) {
      if (dead == index) {
        sim_hw::D415FaultConfig f;
        f.dead_from_s = 0.0;
        cam->set_faults(f);
      }
    }
    return std::unique_ptr<drivers::DepthCamera>(std::move(cam));
  });
}

SimCameras::~SimCameras() { g_current = nullptr; }

void SimCameras::kill(int i) {
  sim_hw::D415FaultConfig f = camera(i).faults();
  f.dead_from_s = 0.0;
  f.dead_until_s = sim_hw::D415FaultConfig{}.dead_until_s;
  camera(i).set_faults(f);
}

void SimCameras::revive(int i) {
  sim_hw::D415FaultConfig f = camera(i).faults();
  f.dead_from_s = f.dead_until_s = sim_hw::D415FaultConfig{}.dead_from_s;
  camera(i).set_faults(f);
}

void SimCameras::bump(int i, double x_m) {
  sim_hw::D415FaultConfig f = camera(i).faults();
  f.bumped_from_s = x_m != 0.0 ? 0.0 : sim_hw::D415FaultConfig::kNever;
  f.bump_x_m = x_m;
  camera(i).set_faults(f);
}

Responder::Responder(drivers::LcmBus& bus, const cell::CellConfig& config) : bus_(bus), config_(config) {
  const twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
  for (const auto& g : config.hardware.grippers) {
    holding_[g.name] = true;
    subscriptions_.push_back(bus_.subscribe<prepreg_lcm::gripper_command_t>(
        drivers::channels::gripper_command(g.name), [this, name = g.name](const prepreg_lcm::gripper_command_t& m) {
          std::lock_guard lock(mutex_);
          ++gripper_commands_;
          holding_[name] = m.action == prepreg_lcm::gripper_command_t::ACTION_CLOSE;
        }));
    if (g.arm.empty()) continue;
    const drivers::ArmConfig& arm = *config.hardware.find_arm(g.arm);
    drivers::IkOptions o;
    o.restarts = 50;
    const auto ik = drivers::solve_inverse_kinematics(
        arm.arm(), drivers::flange_pose_for_jaw(arm, plan.grasps[plan.index_of(g.name)].hold_position_m),
        arm.home_rad, o);
    REQUIRE(ik.status == drivers::IkStatus::kConverged);
    q_[arm.name] = ik.q;
    silent_[arm.name] = false;
    commands_[arm.name] = 0;
    subscriptions_.push_back(bus_.subscribe<lcmt_iiwa_command>(
        drivers::channels::iiwa_command(arm.name), [this, name = arm.name](const lcmt_iiwa_command& m) {
          const auto q = drivers::commanded_positions(m);
          std::lock_guard lock(mutex_);
          ++commands_[name];
          if (q) q_[name] = *q;
        }));
  }
  if (config.cell.clock == drivers::ClockSource::kSim) {
    subscriptions_.push_back(bus_.subscribe<prepreg_lcm::sim_clock_hold_t>(
        std::string(drivers::channels::kSimClockHold), [this](const prepreg_lcm::sim_clock_hold_t& m) { on_hold(m); }));
  } else {
    thread_ = std::thread([this] { run(); });
  }
}

Responder::~Responder() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  for (auto id : subscriptions_) bus_.unsubscribe(id);
}

void Responder::on_hold(const prepreg_lcm::sim_clock_hold_t& hold) {
  if (hold.leaving) return;
  const std::int64_t until = std::max<std::int64_t>(0, hold.until_utime - kEpochUs);
  // Time 0 first, then 10 ms steps up to the hold: the clock, then that time's statuses.
  const auto tick = [&](std::int64_t t) {
    sim_us_ = t;
    prepreg_lcm::sim_clock_t c{};
    c.utime = kEpochUs + t;
    c.sim_us = t;
    c.real_time_factor = 1.0;
    c.state = prepreg_lcm::sim_clock_t::STATE_RUNNING;
    bus_.publish(std::string(drivers::channels::kSimClock), c);
    publish_statuses();
  };
  if (sim_us_ < 0) tick(0);
  while (sim_us_ + 10'000 <= until) tick(sim_us_ + 10'000);
  if (sim_us_ < until) tick(until);
}

void Responder::run() {
  while (!stop_) {
    publish_statuses();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void Responder::publish_statuses() {
  // Copied under the lock, published outside it: a callback holding LCM's dispatch may wait
  // for the lock while a publish waits for LCM.
  std::map<std::string, drivers::JointVector> q;
  std::map<std::string, bool> holding;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [arm, qa] : q_) {
      if (!silent_[arm]) q[arm] = qa;
    }
    holding = holding_;
  }
  for (const auto& [arm, qa] : q) {
    bus_.publish(drivers::channels::iiwa_status(arm),
                 drivers::make_iiwa_status(drivers::utime_now(), qa, drivers::JointVector::Zero(), qa));
  }
  for (const auto& [g, h] : holding) {
    prepreg_lcm::gripper_status_t s{};
    s.utime = drivers::utime_now();
    s.state = h ? prepreg_lcm::gripper_status_t::STATE_CLOSED : prepreg_lcm::gripper_status_t::STATE_OPEN;
    s.width_m = h ? 0.0f : 0.08f;
    s.holding = h;
    bus_.publish(drivers::channels::gripper_status(g), s);
  }
}

void Responder::silence(const std::string& arm, bool silent) {
  std::lock_guard lock(mutex_);
  silent_[arm] = silent;
}
std::uint64_t Responder::commands(const std::string& arm) const {
  std::lock_guard lock(mutex_);
  return commands_.at(arm);
}
std::uint64_t Responder::all_commands() const {
  std::lock_guard lock(mutex_);
  std::uint64_t n = 0;
  for (const auto& [a, c] : commands_) n += c;
  return n;
}
std::uint64_t Responder::gripper_commands() const {
  std::lock_guard lock(mutex_);
  return gripper_commands_;
}
bool Responder::holding(const std::string& gripper) const {
  std::lock_guard lock(mutex_);
  return holding_.at(gripper);
}

}  // namespace cell_test
