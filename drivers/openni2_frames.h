#pragma once
// Frame plumbing of the "openni2" back-end: copying OpenNI2 frames (rows may be padded) into
// our buffers, and keeping the last few colour frames so each depth frame gets the colour frame
// nearest to it in device time (OpenNI2 delivers the two streams independently).

#include <cstdint>
#include <deque>
#include <vector>

#include "drivers/depth_camera.h"

namespace openni {
class VideoFrameRef;
}

namespace drivers {

void copy_openni2_depth(const openni::VideoFrameRef& frame, std::vector<std::uint16_t>& depth_mm);
void copy_openni2_rgb(const openni::VideoFrameRef& frame, std::vector<std::uint8_t>& rgb);

struct ColorImage {
  std::int64_t device_time_us = 0;
  Intrinsics intrinsics;
  std::vector<std::uint8_t> rgb;
};

class ColorHistory {
 public:
  static constexpr std::size_t kCapacity = 4;  // colour frames kept (newest last)

  void clear() { images_.clear(); }
  void add(ColorImage image);
  bool empty() const { return images_.empty(); }
  std::int64_t newest_time_us() const { return images_.back().device_time_us; }
  // The colour image nearest in device time, or nullptr when there is none.
  const ColorImage* nearest(std::int64_t device_time_us) const;

 private:
  std::deque<ColorImage> images_;
};

}  // namespace drivers
