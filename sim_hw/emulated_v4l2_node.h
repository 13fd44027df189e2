#pragma once
// The producer side of one emulated V4L2 capture node: a POSIX shm frame device that sim_hw's
// LD_PRELOAD shim (libprepreg_v4l2_shim.so) serves to a process as /dev/videoN, so the real V4L2
// back-end runs unchanged in CI. See v4l2_shm_layout.h for the layout.
//
//   auto node = EmulatedV4l2Node::create("prepreg_cam0_depth", V4L2_PIX_FMT_Z16, 848, 480, 30);
//   node.publish(bytes, sequence, timestamp_us);   // CLOCK_MONOTONIC us, like uvcvideo
//   node.mark_dead();                              // unplug: the reader gets ENODEV
//   (destructor or destroy(): mark dead and unlink; create again = the device comes back)

#include <cstdint>
#include <cstddef>
#include <string>

#include "sim_hw/v4l2_shm_layout.h"

namespace sim_hw {

class EmulatedV4l2Node {
 public:
  // Creates (replacing a leftover of the same name) shm object "/<name>". Throws
  // std::runtime_error with the name and strerror when it cannot. Bytes per pixel: 2 (Z16, YUYV).
  static EmulatedV4l2Node create(const std::string& name, std::uint32_t pixel_format, int width,
                                 int height, int fps);
  EmulatedV4l2Node() = default;
  EmulatedV4l2Node(EmulatedV4l2Node&& other) noexcept;
  EmulatedV4l2Node& operator=(EmulatedV4l2Node&& other) noexcept;
  ~EmulatedV4l2Node() { destroy(); }

  // Publishes one frame of frame_bytes() bytes (fewer = a short frame).
  void publish(const std::uint8_t* data, std::size_t bytes, std::uint64_t sequence,
               std::int64_t timestamp_us);
  void mark_dead();
  void destroy();  // mark dead, unlink, unmap; safe to repeat

  bool valid() const { return map_.header != nullptr; }
  const std::string& name() const { return name_; }
  std::size_t frame_bytes() const { return map_.header ? map_.header->frame_bytes : 0; }
  int width() const { return map_.header ? static_cast<int>(map_.header->width) : 0; }
  int height() const { return map_.header ? static_cast<int>(map_.header->height) : 0; }

 private:
  std::string name_;
  v4l2_shm::Mapping map_;
  // The shm object's identity: destroy() unlinks the name only while it still names this object
  // (a replacement created under the same name must survive the old node's destruction).
  std::uint64_t device_ = 0, inode_ = 0;
};

// CLOCK_MONOTONIC now, in us (the clock uvcvideo stamps buffers with).
std::int64_t monotonic_us();

}  // namespace sim_hw
