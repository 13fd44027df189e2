#include "drivers/yuyv_color.h"

#include <algorithm>

namespace drivers {
namespace {

std::uint8_t clamp8(int v) { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); }

void put_rgb(int y, int d, int e, std::uint8_t* out) {
  const int c = 298 * (y - 16);
  out[0] = clamp8((c + 409 * e + 128) >> 8);
  out[1] = clamp8((c - 100 * d - 208 * e + 128) >> 8);
  out[2] = clamp8((c + 516 * d + 128) >> 8);
}

}  // namespace

void yuyv_to_rgb(const std::uint8_t* yuyv, int width, int height, std::vector<std::uint8_t>& rgb) {
  const std::size_t pairs = static_cast<std::size_t>(width / 2) * height;
  rgb.resize(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t i = 0; i < pairs; ++i) {
    const std::uint8_t* p = yuyv + 4 * i;
    const int d = p[1] - 128, e = p[3] - 128;
    put_rgb(p[0], d, e, rgb.data() + 6 * i);
    put_rgb(p[2], d, e, rgb.data() + 6 * i + 3);
  }
}

void rgb_to_yuyv(const std::uint8_t* rgb, int width, int height, std::vector<std::uint8_t>& yuyv) {
  const std::size_t pairs = static_cast<std::size_t>(width / 2) * height;
  yuyv.resize(static_cast<std::size_t>(width) * height * 2);
  for (std::size_t i = 0; i < pairs; ++i) {
    const std::uint8_t* a = rgb + 6 * i;
    const std::uint8_t* b = a + 3;
    auto luma = [](const std::uint8_t* p) { return ((66 * p[0] + 129 * p[1] + 25 * p[2] + 128) >> 8) + 16; };
    // Chroma of the pair's mean colour (sums of two pixels, hence the extra halving).
    const int r = a[0] + b[0], g = a[1] + b[1], bl = a[2] + b[2];
    const int u = ((-38 * r - 74 * g + 112 * bl + 256) >> 9) + 128;
    const int v = ((112 * r - 94 * g - 18 * bl + 256) >> 9) + 128;
    std::uint8_t* out = yuyv.data() + 4 * i;
    out[0] = clamp8(luma(a));
    out[1] = clamp8(u);
    out[2] = clamp8(luma(b));
    out[3] = clamp8(v);
  }
}

}  // namespace drivers
