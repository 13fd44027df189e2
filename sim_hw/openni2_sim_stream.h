#pragma once
// One OpenNI2 stream (depth or colour) of a simulated D415 in the OpenNI2 plug-in: answers the
// stream properties OpenNI2's core, its Recorder and our "openni2" back-end ask for, and turns a
// drivers::DepthFrame into an OpenNI2 frame. Only the plug-in includes this (OniDriverAPI.h).

#include <Driver/OniDriverAPI.h>

#include <atomic>
#include <functional>
#include <mutex>
#include <vector>

#include "drivers/depth_camera.h"

namespace sim_hw {

class OpenNI2SimStream : public oni::driver::StreamBase {
 public:
  // `set_mode` asks the device to switch its source camera to a mode; it returns false (and has
  // logged why) when it cannot. `modes` are the modes the device advertises for this sensor.
  OpenNI2SimStream(OniSensorType sensor, const std::vector<OniVideoMode>& modes, OniVideoMode current,
                   drivers::Intrinsics intrinsics, std::function<bool(const OniVideoMode&)> set_mode);

  OniStatus start() override;
  void stop() override;
  bool running() const { return running_; }
  OniSensorType sensor() const { return sensor_; }

  OniStatus getProperty(int property, void* data, int* size) override;
  OniStatus setProperty(int property, const void* data, int size) override;
  OniBool isPropertySupported(int property) override;

  // The device changed mode (for this sensor): new size/rate and intrinsics.
  void set_current(const OniVideoMode& mode, const drivers::Intrinsics& intrinsics);
  // Copies this stream's image out of `frame` and hands it to OpenNI2. Returns false (pushing
  // nothing) when the frame's image does not have this stream's size. The frame's intrinsics
  // become the stream's (its field of view is what OpenNI2 can report of them).
  bool push(const drivers::DepthFrame& frame);

 private:
  OniSensorType sensor_;
  std::vector<OniVideoMode> modes_;
  OniVideoMode current_;
  std::mutex intrinsics_mutex_;  // intrinsics_ is read by OpenNI2 callers, written by push()
  drivers::Intrinsics intrinsics_;
  std::function<bool(const OniVideoMode&)> set_mode_;
  std::atomic<bool> running_{false};
};

}  // namespace sim_hw
