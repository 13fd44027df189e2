#pragma once
// The fake world's arms and grippers (sim_hw::SimulatedArm / SimulatedGripper, the same
// objects cell_world runs) answering the cell controller on ITS bus, for the cell benchmark.
// cell_world's CellWorld handles its bus in run_for() on the caller's thread, but the
// controller already handles the same memq:// bus on the benchmark's thread (and blocks in
// startup()), so here commands arrive through subscriptions dispatched by the controller's
// handle_for (the handling thread), and a thread of our own ticks the devices and publishes their
// statuses (publish is thread-safe); a mutex guards the devices between the two.
// The true sheet is loaded (the grippers grip it) but not stepped: the benchmark's cameras are a
// recording, and its physics would take a core from the cell being measured.
#include <atomic>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "drivers/lcm_bus.h"
#include "sim_hw/simulated_arm.h"
#include "sim_hw/simulated_gripper.h"
#include "sim_hw/true_sheet.h"
#include "sim_hw/world_config.h"

namespace cell_bench {

class BenchRobots {
 public:
  // Loads the world's start (inverse kinematics, hanging equilibrium; throws as CellWorld does)
  // and subscribes on `bus` (call from the thread that will handle the bus).
  BenchRobots(const sim_hw::WorldConfig& config, drivers::LcmBus& bus);
  ~BenchRobots();  // stops the thread and unsubscribes
  BenchRobots(const BenchRobots&) = delete;
  BenchRobots& operator=(const BenchRobots&) = delete;

  void start();  // the status thread (arm_status_hz; grippers at gripper_status_hz)
  void stop();

  std::uint64_t commands_accepted() const;  // arm commands followed so far
  // The true sheet as loaded (hanging from the plan's grasps), for the camera recording.
  const sim_hw::TrueSheet& sheet() const { return *sheet_; }

 private:
  void run();

  sim_hw::WorldConfig config_;
  drivers::LcmBus& bus_;
  std::unique_ptr<sim_hw::TrueSheet> sheet_;
  mutable std::mutex mutex_;  // guards arms_ and grippers_
  std::vector<std::unique_ptr<sim_hw::SimulatedArm>> arms_;
  std::vector<std::unique_ptr<sim_hw::SimulatedGripper>> grippers_;
  std::vector<drivers::LcmBus::SubscriptionId> subscriptions_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace cell_bench
