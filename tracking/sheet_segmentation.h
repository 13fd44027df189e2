#pragma once
// Stage 2 of the tracker: keep the points that are the sheet. A workspace box in the cell frame
// removes the floor, table, robots and walls; a colour rule removes what is inside the box but
// not sheet-coloured (grippers, a hand). Prepreg is dark, so the default rule is a ceiling on
// HSV value; fabrics vary, so an optional hue range and saturation floor/ceiling are config.

#include "tracking/sensor_cloud.h"
#include "tracking/types.h"

namespace tracking {

enum class UnknownColorPolicy {
  kKeep,    // a point the colour camera did not see is kept on geometry alone (default: the
            // depth and colour cameras of a D415 see slightly different areas)
  kReject,  // only points whose colour passes the rule are kept
};

struct ColorRule {
  bool enabled = true;
  double max_value = 0.35;  // HSV value (max of R,G,B)/255; prepreg reflects little light
  double min_value = 0.0;
  double min_saturation = 0.0;  // HSV saturation in [0, 1]
  double max_saturation = 1.0;
  // Hue range in degrees [0, 360); applies only when use_hue. min > max wraps through 0 (reds).
  bool use_hue = false;
  double min_hue_deg = 0.0, max_hue_deg = 360.0;
  UnknownColorPolicy unknown = UnknownColorPolicy::kKeep;
};

struct SegmentationOptions {
  Vec3 box_min_m{-1.0, -1.0, 0.0};  // workspace box, cell frame (m)
  Vec3 box_max_m{1.0, 1.0, 2.0};
  ColorRule color;
};

struct SegmentationCounts {
  int input = 0;
  int outside_box = 0;
  int wrong_color = 0;
  int unknown_color = 0;  // kept or rejected according to the policy
  int kept = 0;
};

// True when the colour passes the rule (r, g, b in 0..255).
bool color_passes(const ColorRule& rule, std::uint8_t r, std::uint8_t g, std::uint8_t b);

// The points of `input` inside the box with an accepted colour, in input order.
SensorCloud segment_sheet(const SensorCloud& input, const SegmentationOptions& options,
                          SegmentationCounts* counts = nullptr);

}  // namespace tracking
