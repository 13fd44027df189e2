// Box and colour segmentation (stage 2).
#include "tracking/sheet_segmentation.h"

#include <algorithm>
#include <cmath>

namespace tracking {

bool color_passes(const ColorRule& rule, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  const double hi = std::max({r, g, b}), lo = std::min({r, g, b});
  const double value = hi / 255.0;
  const double saturation = hi > 0.0 ? (hi - lo) / hi : 0.0;
  if (value > rule.max_value || value < rule.min_value) return false;
  if (saturation < rule.min_saturation || saturation > rule.max_saturation) return false;
  if (!rule.use_hue) return true;
  if (hi == lo) return false;  // grey has no hue, so it cannot be in a hue range
  double hue;
  const double c = hi - lo;
  if (hi == r) {
    hue = 60.0 * std::fmod((g - b) / c + 6.0, 6.0);
  } else if (hi == g) {
    hue = 60.0 * ((b - r) / c + 2.0);
  } else {
    hue = 60.0 * ((r - g) / c + 4.0);
  }
  if (rule.min_hue_deg <= rule.max_hue_deg) {
    return hue >= rule.min_hue_deg && hue <= rule.max_hue_deg;
  }
  return hue >= rule.min_hue_deg || hue <= rule.max_hue_deg;  // wraps through 0 deg
}

SensorCloud segment_sheet(const SensorCloud& input, const SegmentationOptions& options,
                          SegmentationCounts* counts) {
  SegmentationCounts n;
  n.input = static_cast<int>(input.size());
  const Eigen::Vector3f lo = options.box_min_m.cast<float>(), hi = options.box_max_m.cast<float>();
  SensorCloud out;
  out.reserve(input.size() / 2);
  for (std::size_t i = 0; i < input.size(); ++i) {
    const Eigen::Vector3f& p = input.points_m[i];
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) {
      ++n.outside_box;
      continue;
    }
    if (options.color.enabled) {
      if (!input.has_color[i]) {
        ++n.unknown_color;
        if (options.color.unknown == UnknownColorPolicy::kReject) continue;
      } else if (!color_passes(options.color, input.rgb[3 * i], input.rgb[3 * i + 1],
                               input.rgb[3 * i + 2])) {
        ++n.wrong_color;
        continue;
      }
    }
    out.points_m.push_back(p);
    out.rgb.insert(out.rgb.end(), &input.rgb[3 * i], &input.rgb[3 * i] + 3);
    out.has_color.push_back(input.has_color[i]);
    out.camera.push_back(input.camera[i]);
  }
  n.kept = static_cast<int>(out.size());
  if (counts) *counts = n;
  return out;
}

}  // namespace tracking
