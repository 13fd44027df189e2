#pragma once
// Depth camera back-end "test_pattern": a camera whose every pixel is a known function of the
// frame number, like a V4L2 test-pattern generator. It lets a test check that frames passed
// through a driver stack (e.g. the OpenNI2 plug-in) arrive bit-exact, and it can play a faulty
// camera. CameraConfig::uri is empty or comma-separated faults:
//   dead_after=N    read() reports kLost from frame N+1 on, as an unplugged D415 would
//   freeze_after=N  from frame N on every image is frame N's (the counter and clock still run)
//   stale_after=N   from frame N on the device clock stops (images still change)
// It is not a scene simulation (see the "simulated" back-end for that).
//
// Frames: sequence 1, 2, ...; device time = sequence / fps; depth and RGB from
// test_pattern_depth_mm / test_pattern_rgb; read() returns at once (whoever drives it paces it).

#include <cstdint>

#include "drivers/depth_camera.h"

namespace sim_hw {

std::uint16_t test_pattern_depth_mm(std::uint64_t sequence, int x, int y, int width, int height);
void test_pattern_rgb(std::uint64_t sequence, int x, int y, std::uint8_t rgb[3]);

class TestPatternCamera : public drivers::DepthCamera {
 public:
  drivers::DriverResult configure(const drivers::CameraConfig& config) override;
  drivers::DriverResult activate() override;
  drivers::ReadStatus read(drivers::DepthFrame& frame) override;
  drivers::CameraHealth health() const override { return health_; }
  drivers::DriverResult deactivate() override;

 private:
  drivers::CameraConfig config_;
  drivers::CameraHealth health_;
  std::uint64_t sequence_ = 0;
  std::int64_t dead_after_ = -1;                       // frames before the camera "dies"; -1 = never
  std::int64_t freeze_after_ = -1, stale_after_ = -1;  // -1 = never
};

// Registers "test_pattern" with the drivers/ registry. Not part of
// register_simulated_depth_cameras(): only test set-ups (the OpenNI2 plug-in's test hook) add it.
void register_test_pattern_camera();

}  // namespace sim_hw
