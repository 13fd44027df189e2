#pragma once
// A RealSense D415 through the kernel's uvcvideo driver (back-end "v4l2"): the depth node
// streams Z16 and the colour node YUYV, each a V4l2CaptureNode. URI:
//   "depth=/dev/video0,color=/dev/video2"   (color= optional; prefer /dev/v4l/by-id/ paths)
// A D415 shows several nodes per sensor (metadata too); the depth one is usually the first.
// Depth frames pace read(); the colour frame nearest in time (within one colour frame period) is
// paired with each, otherwise the frame goes out without colour (color_intrinsics.width 0).
// V4L2 cannot read the calibration or the serial: intrinsics come from the config, and a
// configured serial must appear in the depth path (by-id names carry it).
// A frame older than stale_after on arrival (buffer timestamps are CLOCK_MONOTONIC, the host's
// steady clock) -> kStale.
// A lost device (ENODEV/EIO...) -> ReadStatus::kLost and state Lost; later reads try to reopen
// both nodes, backing off from 100 ms to 2 s between attempts; read() never sleeps while lost.

#include <chrono>
#include <memory>
#include <string>

#include "drivers/depth_camera.h"
#include "drivers/v4l2_capture_node.h"
#include "drivers/v4l2_io.h"

namespace drivers {

struct V4l2D415Uri {
  std::string depth_path, color_path;  // color_path empty = no colour
};
// Empty `error` when the URI parsed.
V4l2D415Uri parse_v4l2_d415_uri(const std::string& uri, std::string& error);

class V4l2D415Camera : public DepthCamera {
 public:
  explicit V4l2D415Camera(std::shared_ptr<V4l2Io> io = std::make_shared<LibcV4l2Io>());
  ~V4l2D415Camera() override;

  DriverResult configure(const CameraConfig& config) override;
  DriverResult activate() override;
  ReadStatus read(DepthFrame& frame) override;
  CameraHealth health() const override { return health_; }
  DriverResult deactivate() override;

 private:
  DriverResult open_nodes();  // opens both; on failure closes both
  DriverResult start_nodes();
  ReadStatus lose(const std::string& why);
  bool reopen_due();
  // Fills frame.rgb from the colour frame nearest to depth_time_us; false if the node was lost.
  bool pair_color(std::int64_t depth_time_us, std::int64_t deadline_ms, DepthFrame& frame);

  std::shared_ptr<V4l2Io> io_;
  V4l2CaptureNode depth_, color_;
  CameraConfig config_;
  V4l2D415Uri uri_;
  bool active_ = false, lost_ = false;
  std::chrono::steady_clock::time_point next_reopen_{};
  std::chrono::milliseconds backoff_{0};
  CapturedImage depth_image_, color_image_, color_scratch_, color_pending_;
  bool have_color_image_ = false, have_color_pending_ = false;
  CameraHealth health_;
};

}  // namespace drivers
