#pragma once
// One simulated D415 inside the OpenNI2 plug-in: an OpenNI2 device whose frames come from a
// drivers::DepthCamera (the "source", made through the registry from the plug-in's config).
// It advertises the D415's depth and colour modes; choosing another mode reconfigures the source
// (intrinsics scaled to the new resolution). Frames are pushed by a thread at the mode's rate or,
// with on_demand, one per OpenNI2 wait (OpenNI2 calls tryManualTrigger while a reader waits),
// which makes CI runs deterministic. When the source reports kLost the device calls `on_lost`
// once (the driver then tells OpenNI2 the device was disconnected) and pushes nothing more.

#include <Driver/OniDriverAPI.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "drivers/depth_camera.h"
#include "sim_hw/openni2_sim_config.h"
#include "sim_hw/openni2_sim_stream.h"

namespace sim_hw {

class OpenNI2SimDevice : public oni::driver::DeviceBase {
 public:
  OpenNI2SimDevice(const OpenNI2SimDeviceConfig& config, std::unique_ptr<drivers::DepthCamera> source,
                   oni::driver::DriverServices& services, std::function<void()> on_lost);
  ~OpenNI2SimDevice() override;

  // Configures and activates the source; false (with the reason logged to OpenNI2) on failure.
  bool start_source();

  OniStatus getSensorInfoList(OniSensorInfo** sensors, int* count) override;
  oni::driver::StreamBase* createStream(OniSensorType sensor) override;
  void destroyStream(oni::driver::StreamBase* stream) override;
  OniStatus getProperty(int property, void* data, int* size) override;
  OniStatus setProperty(int property, const void* data, int size) override;
  OniBool isPropertySupported(int property) override;
  OniStatus tryManualTrigger() override;

 private:
  bool set_mode(OniSensorType sensor, const OniVideoMode& mode);
  void pump_loop();
  void pump_once();  // one source read; pushes the frame to the running streams

  OpenNI2SimDeviceConfig config_;  // source config in its current modes
  std::unique_ptr<drivers::DepthCamera> source_;
  oni::driver::DriverServices& services_;
  std::function<void()> on_lost_;
  std::vector<OniVideoMode> depth_modes_, color_modes_;
  std::vector<OniSensorInfo> sensors_;

  std::mutex source_mutex_;   // source_ and config_ modes
  std::mutex streams_mutex_;  // streams_
  std::vector<OpenNI2SimStream*> streams_;
  drivers::DepthFrame frame_;
  std::atomic<bool> lost_{false};
  std::atomic<bool> stop_{false};
  std::thread pump_;
};

}  // namespace sim_hw
