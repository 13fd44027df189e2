#pragma once
// One camera of the fake world: a simulated D415 (wall clock, the cell config's modes, the true
// pose) that sees the world's current scene, served as an emulated D415 V4L2 device through a
// V4l2CameraBridge from its own thread, so the cell process reads it with the real V4L2 back-end
// through the LD_PRELOAD shim. Faults from SIM_FAULT map onto the camera's D415FaultConfig,
// starting or ending at the moment they arrive:
//   "dead"   the device is lost (the bridge unplugs its nodes); cleared: it comes back (plug in)
//   "frozen" the same image over and over (sequence and timestamps advance)
//   "stale"  the device clock stops (every frame carries the same timestamp)
//   "drop"   each frame is lost with probability 0.5 (sequence gaps, occasional timeouts)

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "sim_hw/simulated_d415.h"
#include "sim_hw/v4l2_camera_bridge.h"
#include "sim_hw/world_config.h"

namespace sim_hw {

class EmulatedCameraRig {
 public:
  // Configures and activates the camera and creates the shm nodes; throws std::runtime_error
  // naming the camera when it cannot.
  EmulatedCameraRig(const WorldCamera& camera, SceneSource scene);
  ~EmulatedCameraRig();
  EmulatedCameraRig(const EmulatedCameraRig&) = delete;
  EmulatedCameraRig& operator=(const EmulatedCameraRig&) = delete;

  void start();  // the serving thread
  void stop();   // joins it and deactivates the camera (the nodes go with the bridge)

  // False when `fault` is not a camera fault.
  bool apply_fault(const std::string& fault, bool active);

  const std::string& name() const { return camera_.config.name; }
  std::string emulation_spec() const;  // "/dev/video0=<node>,/dev/video1=<node>"
  std::uint64_t frames() const { return frames_.load(); }
  std::uint64_t lost_reads() const { return lost_.load(); }

 private:
  void run();
  double now_s() const;

  WorldCamera camera_;
  SimulatedD415Camera d415_;
  std::unique_ptr<V4l2CameraBridge> bridge_;
  std::chrono::steady_clock::time_point activated_at_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> frames_{0}, lost_{0};
};

}  // namespace sim_hw
