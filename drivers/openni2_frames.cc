#include "drivers/openni2_frames.h"

#include <OpenNI.h>

#include <cstdlib>
#include <cstring>

namespace drivers {
namespace {

// Row by row: OpenNI2 frames carry a stride that may exceed width * pixel size.
template <typename T>
void copy_rows(const openni::VideoFrameRef& frame, int values_per_pixel, std::vector<T>& out) {
  const std::size_t row_values = static_cast<std::size_t>(frame.getWidth()) * values_per_pixel;
  out.resize(row_values * frame.getHeight());
  const auto* src = static_cast<const std::uint8_t*>(frame.getData());
  for (int y = 0; y < frame.getHeight(); ++y) {
    std::memcpy(out.data() + y * row_values, src + static_cast<std::size_t>(y) * frame.getStrideInBytes(),
                row_values * sizeof(T));
  }
}

}  // namespace

void copy_openni2_depth(const openni::VideoFrameRef& frame, std::vector<std::uint16_t>& depth_mm) {
  copy_rows(frame, 1, depth_mm);
}

void copy_openni2_rgb(const openni::VideoFrameRef& frame, std::vector<std::uint8_t>& rgb) {
  copy_rows(frame, 3, rgb);
}

void ColorHistory::add(ColorImage image) {
  images_.push_back(std::move(image));
  if (images_.size() > kCapacity) images_.pop_front();
}

const ColorImage* ColorHistory::nearest(std::int64_t device_time_us) const {
  const ColorImage* best = nullptr;
  for (const ColorImage& image : images_) {
    if (best == nullptr || std::llabs(image.device_time_us - device_time_us) <
                               std::llabs(best->device_time_us - device_time_us)) {
      best = &image;
    }
  }
  return best;
}

}  // namespace drivers
