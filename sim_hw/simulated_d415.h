#pragma once
// A simulated RealSense D415 behind the drivers::DepthCamera interface (back-end "simulated").
// Each frame renders the scene snapshot for the frame's time into the left IR (depth) imager, the
// right IR imager (for the stereo shadow) and the colour imager, then applies the D415 error
// model and any faults. The scene comes either from a SceneSource given in code (the cell's fake
// world passes the true sheet) or, for the registered back-end, from a scene JSON file named by
// CameraConfig::uri (see d415_scene_file.h); a non-empty uri replaces all constructor options.
//
// Calibration: the simulated unit reports the nominal D415 model (d415_model.h) unless the config
// gives intrinsics (width != 0: must match the mode) or a non-identity depth_to_color, which then
// act as that unit's factory calibration. Distortion coefficients are reported but not simulated.
//
// Clock: kSimulated, each read() advances simulation time to the next frame (1/fps) instantly, so
// runs are deterministic for a seed; host_time_us = (steady clock at activate) + simulation time.
// kWall, read() sleeps until the next frame is due (at most read_timeout) and host_time_us is the
// steady clock on delivery; a late reader gets the newest due frame (older ones count as
// dropped, as with a real driver's overwritten buffers). kProcess: the process's clock
// (drivers::host_clock_us(), the fake world's simulation time in a process on "clock": "sim"):
// read() never waits, since the reader's own thread may be what holds that clock; it returns
// the newest frame due by now (host_time_us its due time) or, when none is new yet, a timeout.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <random>
#include <vector>

#include "drivers/depth_camera.h"
#include "sim_hw/d415_error_model.h"
#include "sim_hw/d415_faults.h"
#include "sim_hw/depth_renderer.h"
#include "sim_hw/render_scene.h"

namespace sim_hw {

enum class SimClock { kSimulated, kWall, kProcess };

struct SimulatedD415Options {
  SceneSource scene;  // empty: CameraConfig::uri must name a scene file
  D415NoiseConfig noise;
  D415FaultConfig faults;
  std::uint64_t seed = 1;
  SimClock clock = SimClock::kSimulated;
};

class SimulatedD415Camera : public drivers::DepthCamera {
 public:
  SimulatedD415Camera() = default;  // scene, noise, faults, seed, clock from the uri's scene file
  explicit SimulatedD415Camera(SimulatedD415Options options);

  drivers::DriverResult configure(const drivers::CameraConfig& config) override;
  drivers::DriverResult activate() override;
  drivers::ReadStatus read(drivers::DepthFrame& frame) override;
  drivers::CameraHealth health() const override;
  drivers::DriverResult deactivate() override;

  // Faults on demand, e.g. from the cell's fake world or a test on another thread; they take
  // effect at the next read().
  void set_faults(const D415FaultConfig& faults);
  D415FaultConfig faults() const;
  // Simulation time of the last frame (or timeout) since activate (s); safe from any thread.
  double sim_time_s() const { return sim_time_s_.load(); }

 private:
  double now_s() const;
  void wait_until(double t_s);
  bool dropped(const D415FaultConfig& faults, std::uint64_t index, double t_s);
  // Renders the scene at t_s as seen from camera_to_cell (the configured pose, or a bumped one).
  void render(double t_s, const Eigen::Isometry3d& camera_to_cell, drivers::DepthFrame& frame);

  SimulatedD415Options options_;
  drivers::CameraConfig config_;
  drivers::Intrinsics depth_k_, color_k_;
  Eigen::Isometry3d depth_to_color_ = Eigen::Isometry3d::Identity();
  std::mt19937_64 noise_rng_, fault_rng_;
  RenderedView left_, right_, color_;  // reused buffers
  drivers::CameraHealth health_;
  bool configured_ = false, active_ = false, lost_ = false;
  std::uint64_t next_index_ = 0;
  bool have_last_ = false;
  std::uint64_t last_sequence_ = 0;
  std::int64_t last_device_time_us_ = 0;
  std::vector<std::uint16_t> last_depth_;
  std::vector<std::uint8_t> last_rgb_;
  std::atomic<double> sim_time_s_{0.0};
  mutable std::mutex faults_mutex_;  // guards options_.faults
  std::chrono::steady_clock::time_point activated_at_;
  std::int64_t host_epoch_us_ = 0;
};

}  // namespace sim_hw
