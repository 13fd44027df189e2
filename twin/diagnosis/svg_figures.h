#pragma once
// The report's pictures as SVG text, written by hand (no plotting dependency): a residual map
// of one stage in material coordinates and a grouped bar chart. Colours on a diverging
// blue-white-red scale.

#include <string>
#include <vector>

#include "twin/diagnosis/residual_analysis.h"
#include "twin/diagnosis/residual_field.h"

namespace twin::diagnosis {

// "#rrggbb" for value on a diverging scale: blue at -limit, white at 0, red at +limit (clamped).
std::string diverging_colour(double value, double limit);

// Escapes &, <, >, " for SVG/XML text and attributes.
std::string xml_escape(const std::string& text);

struct MapPanel {
  std::string title;
  const ResidualField* field = nullptr;
  const StageResult* result = nullptr;  // its analysis (regions outlined when significant); may be null
  int stage = 0;                        // index into field->stages
};

// Panels side by side (before / after), one circle per seen marker coloured by the normal
// residual in mm on [-limit_mm, limit_mm], with a colour legend.
std::string residual_map_svg(const std::vector<MapPanel>& panels, double limit_mm);

struct BarGroup {
  std::string label;            // stage label
  std::vector<double> values;   // one per series (NaN: no bar)
};

// Grouped bars (values in mm) with one colour per series, a legend and an optional horizontal
// reference line (e.g. the noise floor; NaN for none).
std::string bar_chart_svg(const std::string& title, const std::vector<std::string>& series,
                          const std::vector<BarGroup>& groups, double reference_mm,
                          const std::string& reference_label);

}  // namespace twin::diagnosis
