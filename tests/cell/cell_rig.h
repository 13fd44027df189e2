#pragma once
// A whole cell in one process for the cell controller's tests, on an in-process LCM bus
// (memq://): the paper's four-grasp ply hanging as the plan says (the twin's own equilibrium,
// the "truth"), three simulated D415s (back-end "test_sim") rendering it from the fake cell's
// camera poses, and a test-side arm/gripper responder that publishes IIWA_STATUS for the
// commanded joints and GRIPPER_STATUS, with switches to silence an arm.
//
// On "clock": "sim" (the rig's default, as the fake cell's) the responder is also the world's
// clock: the controller's holds (SIM_CLOCK_HOLD) run it on in 10 ms steps, each a SIM_CLOCK and
// the statuses of that time, all on the controller's own thread, and the cameras give the frames
// due by the process's clock; so a test's cycles are the same however busy the machine.
// On "clock": "wall" the cameras run on the wall and the responder publishes every 10 ms from a
// thread.
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include <prepreg_lcm/sim_clock_hold_t.hpp>

#include "cell/cell_config.h"
#include "drivers/iiwa_kinematics.h"
#include "drivers/lcm_bus.h"
#include "sim_hw/simulated_d415.h"
#include "tests/support/temp_dir.h"

namespace cell_test {

// The fake cell's config (cell/examples/fake_cell.json) made runnable in-process: cameras on
// back-end "test_sim", LCM memq://, a coarser twin mesh and short start-up timeouts. Written
// into `dir` with the material and plan files; edit() lets a test change it first.
struct RigFiles {
  nlohmann::json config;
  nlohmann::json material;
  nlohmann::json plan;
};
RigFiles default_files();
std::string write_files(const testing_support::TempDir& dir, const RigFiles& files);  // config path

// Registers back-end "test_sim" rendering the plan's hanging sheet; cameras are kept in
// creation order (the cell opens them in config order) so tests can inject faults.
class SimCameras {
 public:
  explicit SimCameras(const cell::CellConfig& config);
  ~SimCameras();
  sim_hw::SimulatedD415Camera& camera(int i) { return *cameras_.at(i); }
  int created() const { return static_cast<int>(cameras_.size()); }
  void kill(int i);
  void revive(int i);
  void kill_from_start(int i) { dead_from_start_.push_back(i); }
  // Camera i knocked on its mount: it sees the cell from `x_m` along its own x (0: back in place).
  void bump(int i, double x_m);
  // The true sheet's vertices (cell frame, m), as the fake world publishes on SIM_SHEET_TRUTH.
  const std::vector<Eigen::Vector3d>& truth() const { return scene_->meshes.front().vertices; }

 private:
  std::shared_ptr<const sim_hw::RenderScene> scene_;
  std::vector<sim_hw::SimulatedD415Camera*> cameras_;  // owned by the cell's camera set
  std::vector<int> dead_from_start_;
  sim_hw::SimClock clock_;  // kProcess on the simulation clock, kWall on the wall
};

// Arms that go where they are commanded (instantly, within limits) and grippers that open when
// told; statuses every 10 ms (of the simulation clock it serves, or from a thread on the wall).
class Responder {
 public:
  Responder(drivers::LcmBus& bus, const cell::CellConfig& config);
  ~Responder();
  void silence(const std::string& arm, bool silent);
  std::uint64_t commands(const std::string& arm) const;
  std::uint64_t all_commands() const;
  std::uint64_t gripper_commands() const;
  bool holding(const std::string& gripper) const;

 private:
  void run();
  void publish_statuses();
  void on_hold(const prepreg_lcm::sim_clock_hold_t& hold);
  drivers::LcmBus& bus_;
  cell::CellConfig config_;
  mutable std::mutex mutex_;
  std::map<std::string, drivers::JointVector> q_;
  std::map<std::string, bool> silent_;
  std::map<std::string, std::uint64_t> commands_;
  std::map<std::string, bool> holding_;
  std::uint64_t gripper_commands_ = 0;
  std::vector<drivers::LcmBus::SubscriptionId> subscriptions_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::int64_t sim_us_ = -1;  // the clock it serves (us since its epoch); -1: not started
  static constexpr std::int64_t kEpochUs = 1'700'000'000'000'000;
};

}  // namespace cell_test
