#pragma once
// The fake-hardware world of the cell, in one object: the true sheet, the simulated iiwa arms and
// grippers, the simulated D415s served as emulated V4L2 devices, speaking the channels real
// drivers speak: IIWA_COMMAND_/IIWA_STATUS_<ARM>, GRIPPER_COMMAND_/GRIPPER_STATUS_<G>, plus the
// fake world's own SIM_SHEET_TRUTH (published), SIM_FAULT (obeyed for its cameras and arms;
// other targets such as "twin" are left to their owners) and its simulation clock SIM_CLOCK
// (sim_hw/world_clock.h).
//
// Everything runs on the world's simulation clock, on the caller's thread, in a fixed order at
// each time: commands and faults received so far, the arms (at their status rate) and grippers,
// the physics steps, the truth, the cameras' frames (rendered in parallel), then the clock. The
// clock advances to the next event as fast as the work allows, never faster than
// max_real_time_factor, and never past a lockstep client's hold; so a run with lockstep clients
// repeats exactly, and a slow machine makes the world slower, not different.
//
// Construction does the initial load (inverse kinematics for the arms, the hanging equilibrium
// of the sheet; a few seconds), creates the emulated device nodes and serves time 0. The bus
// must outlive the world; its subscriptions are made in the constructor, handled by run_for and
// removed by the destructor, so all belong to one thread.

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "drivers/lcm_bus.h"
#include "sim_hw/emulated_camera_rig.h"
#include "sim_hw/simulated_arm.h"
#include "sim_hw/simulated_gripper.h"
#include "sim_hw/true_sheet.h"
#include "sim_hw/world_clock.h"
#include "sim_hw/world_config.h"

namespace sim_hw {

struct WorldCounters {
  std::uint64_t arm_commands = 0, arm_commands_rejected = 0;
  std::uint64_t gripper_commands = 0, gripper_commands_rejected = 0;
  std::uint64_t faults_applied = 0, faults_rejected = 0, faults_not_ours = 0;
  std::uint64_t truth_published = 0;
};

struct WorldSnapshot {
  double sim_time_s = 0;
  double real_time_factor = 0;  // over about the last wall second
  std::string held_by;           // the lockstep client the clock waits on, "" when running
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
  CellWorld(WorldConfig config, drivers::LcmBus& bus, WorldClockOptions clock = {});
  ~CellWorld();
  CellWorld(const CellWorld&) = delete;
  CellWorld& operator=(const CellWorld&) = delete;

  // Runs the world for `duration` of wall time (however much simulated time that is). Returns
  // early when *stop is set.
  void run_for(std::chrono::duration<double> duration, const std::atomic<bool>* stop = nullptr);
  // Runs the world until its clock reaches sim_s (seconds since the start), without the rate
  // limit's waits beyond it; returns false when a lockstep client holds the clock short of it for
  // `patience` of wall time, or *stop was set.
  bool run_until(double sim_s, std::chrono::duration<double> patience = std::chrono::seconds(10),
                 const std::atomic<bool>* stop = nullptr);
  double sim_time_s() const { return clock_->sim_s(); }
  WorldClock& clock() { return *clock_; }

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
  // One turn of the loop: commands, then the clock to min(next event, hold), then that
  // time's events. False when it could not move (held) or was stopped.
  bool turn(std::int64_t until_us, const std::atomic<bool>* stop);
  void drain_bus();
  std::int64_t next_event_us() const;
  void serve_due_events();
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

  std::unique_ptr<WorldClock> clock_;
  // Event counters: the k-th event of each kind falls at round(k * period) us, so none drifts.
  std::int64_t arm_ticks_ = 0, gripper_ticks_ = 0, physics_steps_ = 0, truths_ = 0;
  mutable std::mutex counters_mutex_;
  WorldCounters counters_;
};

}  // namespace sim_hw
