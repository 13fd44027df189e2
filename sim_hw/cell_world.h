#pragma once
// The fake-hardware world of the cell, in one object: the true sheet (physics thread), the
// simulated iiwa arms and grippers (on the LCM thread: the caller of run_for), the simulated
// D415s served as emulated V4L2 devices (one thread each), speaking the channels real drivers
// speak: IIWA_COMMAND_/IIWA_STATUS_<ARM>, GRIPPER_COMMAND_/GRIPPER_STATUS_<G>, plus the fake
// world's own SIM_SHEET_TRUTH (published) and SIM_FAULT (obeyed for its cameras and arms; other
// targets such as "twin" are left to their owners).
//
// Construction does the initial load (inverse kinematics for the arms, the hanging equilibrium
// of the sheet; a few seconds) and creates the emulated device nodes; start() starts the
// physics and camera threads. The bus must outlive the world; its subscriptions are made in the
// constructor and handled by run_for, and removed by the destructor, so all belong to one thread.

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/lcm_bus.h"
#include "sim_hw/emulated_camera_rig.h"
#include "sim_hw/simulated_arm.h"
#include "sim_hw/simulated_gripper.h"
#include "sim_hw/true_sheet.h"
#include "sim_hw/world_config.h"

namespace sim_hw {

struct WorldCounters {
  std::uint64_t arm_commands = 0, arm_commands_rejected = 0;
  std::uint64_t gripper_commands = 0, gripper_commands_rejected = 0;
  std::uint64_t faults_applied = 0, faults_rejected = 0, faults_not_ours = 0;
  std::uint64_t truth_published = 0, physics_overruns = 0;
};

struct WorldSnapshot {
  double sim_time_s = 0, wall_time_s = 0;
  StepStats physics;
  double sag_m = 0;
  std::vector<std::pair<std::string, std::uint64_t>> camera_frames;
  std::vector<std::string> holding;  // grippers holding the sheet
  int arms_moving = 0;
  WorldCounters counters;
};

class CellWorld {
 public:
  // Throws std::runtime_error saying why (e.g. an unreachable hold position naming the gripper,
  // an initial load that did not converge, device nodes that could not be created).
  CellWorld(WorldConfig config, drivers::LcmBus& bus);
  ~CellWorld();
  CellWorld(const CellWorld&) = delete;
  CellWorld& operator=(const CellWorld&) = delete;

  void start();  // physics and camera threads
  void stop();   // joins them

  // The LCM thread's work for `duration`: handles commands and faults, follows the commands at
  // the arms' status rate, publishes arm and gripper statuses. Returns early when *stop is set.
  void run_for(std::chrono::duration<double> duration, const std::atomic<bool>* stop = nullptr);

  // PREPREG_V4L2_EMULATION value for every camera's device paths.
  std::string emulation_spec() const;
  WorldSnapshot snapshot() const;
  const TrueSheet& sheet() const { return *sheet_; }
  TrueSheet& sheet() { return *sheet_; }
  const twin::SolveReport& load_report() const { return load_report_; }
  const std::vector<std::unique_ptr<SimulatedArm>>& arms() const { return arms_; }
  const std::vector<std::unique_ptr<SimulatedGripper>>& grippers() const { return grippers_; }
  std::shared_ptr<const RenderScene> scene() const;

 private:
  void subscribe();
  void on_fault(const std::string& target, const std::string& fault, bool active);
  void physics_loop();
  void update_scene();
  void publish_truth();
  void tick_devices(double dt_s, bool publish_grippers);

  WorldConfig config_;
  drivers::LcmBus& bus_;
  std::vector<drivers::LcmBus::SubscriptionId> subscriptions_;  // dropped with the world
  std::unique_ptr<TrueSheet> sheet_;
  twin::SolveReport load_report_;
  std::vector<std::unique_ptr<SimulatedArm>> arms_;
  std::vector<std::unique_ptr<SimulatedGripper>> grippers_;
  std::vector<std::unique_ptr<EmulatedCameraRig>> cameras_;

  mutable std::mutex scene_mutex_;
  std::shared_ptr<const RenderScene> scene_;
  SceneMesh sheet_mesh_;  // physics thread: reused vertex buffer

  std::thread physics_;
  std::atomic<bool> stop_physics_{false};
  std::atomic<double> sim_time_s_{0.0};
  std::chrono::steady_clock::time_point started_at_;
  mutable std::mutex counters_mutex_;
  WorldCounters counters_;
  std::chrono::steady_clock::time_point next_arm_tick_, next_gripper_tick_;
};

}  // namespace sim_hw
