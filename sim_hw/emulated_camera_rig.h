#pragma once
// One camera of the fake world: a simulated D415 (on the world's simulation clock, the cell
// config's modes, the true pose) that sees the world's current scene, served as an emulated D415
// V4L2 device through a V4l2CameraBridge, so the cell process reads it with the real V4L2
// back-end through the LD_PRELOAD shim. The world calls serve_frame() when its clock reaches
// next_frame_us(): the camera renders that frame at once (its noise drawn in frame order, so a
// run repeats) and the bridge publishes it. Faults from SIM_FAULT map onto the camera's
// D415FaultConfig, starting or ending at the world time they arrive:
//   "dead"   the device is lost (the bridge unplugs its nodes); cleared: it comes back (plug in)
//   "frozen" the same image over and over (sequence and timestamps advance)
//   "stale"  the device clock stops (every frame carries the same timestamp)
//   "drop"   each frame is lost with probability 0.5 (sequence gaps, occasional timeouts)

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

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

  // Renders and publishes the frame due at next_frame_us() (or the camera's loss or timeout).
  void serve_frame();
  // When the next frame is due, us of simulation time since the world started.
  std::int64_t next_frame_us() const { return next_frame_us_; }

  // At t_s of simulation time since the world started. False when `fault` is not a camera fault.
  bool apply_fault(const std::string& fault, bool active, double t_s);

  const std::string& name() const { return camera_.config.name; }
  std::string emulation_spec() const;  // "/dev/video0=<node>,/dev/video1=<node>"
  std::uint64_t frames() const { return frames_.load(); }
  std::uint64_t lost_reads() const { return lost_.load(); }

 private:
  WorldCamera camera_;
  SimulatedD415Camera d415_;
  std::unique_ptr<V4l2CameraBridge> bridge_;
  std::int64_t next_frame_us_ = 0;
  std::atomic<std::uint64_t> frames_{0}, lost_{0};
};

}  // namespace sim_hw
