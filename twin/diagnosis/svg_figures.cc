#include "twin/diagnosis/svg_figures.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

namespace twin::diagnosis {
namespace {

constexpr double kPanelWidth = 340.0;   // px, the sheet's drawing width in a map panel
constexpr double kMargin = 30.0;        // px
constexpr double kLegendWidth = 90.0;   // px
constexpr double kMarkerRadius = 5.0;   // px

// One series colour each (colour-blind safe Okabe-Ito hues).
const char* const kSeriesColours[] = {"#999999", "#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9"};

}  // namespace

std::string diverging_colour(double value, double limit) {
  double t = limit > 0.0 && std::isfinite(value) ? std::clamp(value / limit, -1.0, 1.0) : 0.0;
  // White at 0 towards (33, 102, 172) blue or (178, 24, 43) red.
  const double r = t >= 0 ? 255 + t * (178 - 255) : 255 + -t * (33 - 255);
  const double g = t >= 0 ? 255 + t * (24 - 255) : 255 + -t * (102 - 255);
  const double b = t >= 0 ? 255 + t * (43 - 255) : 255 + -t * (172 - 255);
  return fmt::format("#{:02x}{:02x}{:02x}", static_cast<int>(std::lround(r)), static_cast<int>(std::lround(g)),
                     static_cast<int>(std::lround(b)));
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string residual_map_svg(const std::vector<MapPanel>& panels, double limit_mm) {
  double height = 0.0;
  for (const MapPanel& p : panels) {
    const FieldTrial& t = p.field->trials.at(p.field->stages.at(p.stage).trial);
    const Vec2 size = t.sheet_max_uv_m - t.sheet_min_uv_m;
    height = std::max(height, kPanelWidth * size.y() / std::max(size.x(), 1e-9));
  }
  const double width = panels.size() * (kPanelWidth + kMargin) + kMargin + kLegendWidth;
  const double total_height = height + 3 * kMargin;
  std::ostringstream s;
  s << fmt::format(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="{:.0f}" height="{:.0f}" font-family="sans-serif" font-size="12">)svg",
                   width, total_height)
    << "\n";
  s << fmt::format(R"svg(<rect x="0" y="0" width="{:.0f}" height="{:.0f}" fill="white"/>)svg", width, total_height) << "\n";
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const MapPanel& p = panels[k];
    const FieldStage& stage = p.field->stages.at(p.stage);
    const FieldTrial& t = p.field->trials.at(stage.trial);
    const Vec2 size = t.sheet_max_uv_m - t.sheet_min_uv_m;
    const double scale = kPanelWidth / std::max(size.x(), 1e-9);
    const double x0 = kMargin + k * (kPanelWidth + kMargin), y0 = 2 * kMargin;
    // Material v points up in the picture.
    auto px = [&](const Vec2& uv) {
      return Vec2(x0 + (uv.x() - t.sheet_min_uv_m.x()) * scale, y0 + (t.sheet_max_uv_m.y() - uv.y()) * scale);
    };
    s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">{}</text>)svg", x0, kMargin, xml_escape(p.title)) << "\n";
    s << fmt::format(R"svg(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="#f4f4f4" stroke="#777"/>)svg", x0, y0,
                     size.x() * scale, size.y() * scale)
      << "\n";
    if (p.result)
      for (const RegionResult& r : p.result->regions) {
        if (!r.test.significant) continue;
        const Vec2 a = px(Vec2(r.min_uv_m.x(), r.max_uv_m.y()));
        s << fmt::format(R"svg(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="none" stroke="black" stroke-width="2.5" stroke-dasharray="6,3"/>)svg",
                         a.x(), a.y(), (r.max_uv_m.x() - r.min_uv_m.x()) * scale, (r.max_uv_m.y() - r.min_uv_m.y()) * scale)
          << "\n";
      }
    for (int i : p.field->samples_of_stage(p.stage)) {
      const ResidualSample& m = p.field->samples[i];
      const Vec2 c = px(m.uv_m);
      s << fmt::format(R"svg(<circle cx="{:.1f}" cy="{:.1f}" r="{:.1f}" fill="{}" stroke="#555" stroke-width="0.4"/>)svg", c.x(),
                       c.y(), kMarkerRadius, diverging_colour(1e3 * m.normal_residual_m, limit_mm))
        << "\n";
    }
    s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">u (weft) &#8594;  mean error {:.2f} mm</text>)svg", x0,
                     y0 + size.y() * scale + 16, 1e3 * stage.mean_error_m)
      << "\n";
  }
  // Legend: a column of colour steps from +limit (top) to -limit.
  const double lx = width - kLegendWidth + 10, ly = 2 * kMargin, lh = std::max(height, 100.0);
  constexpr int kSteps = 20;
  for (int i = 0; i < kSteps; ++i) {
    const double v = limit_mm * (1.0 - 2.0 * (i + 0.5) / kSteps);
    s << fmt::format(R"svg(<rect x="{:.1f}" y="{:.1f}" width="16" height="{:.2f}" fill="{}"/>)svg", lx, ly + i * lh / kSteps,
                     lh / kSteps + 0.5, diverging_colour(v, limit_mm))
      << "\n";
  }
  s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">+{:.2f}</text>)svg", lx + 20, ly + 10, limit_mm) << "\n";
  s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">0</text>)svg", lx + 20, ly + lh / 2 + 4) << "\n";
  s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">-{:.2f}</text>)svg", lx + 20, ly + lh, limit_mm) << "\n";
  s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">normal mm</text>)svg", lx - 6, ly - 8) << "\n";
  s << "</svg>\n";
  return s.str();
}

std::string bar_chart_svg(const std::string& title, const std::vector<std::string>& series,
                          const std::vector<BarGroup>& groups, double reference_mm, const std::string& reference_label) {
  constexpr double kBar = 12.0, kGap = 14.0, kPlotHeight = 220.0, kLeft = 60.0, kTop = 40.0, kBottom = 110.0;
  const double group_width = series.size() * kBar + kGap;
  const double width = kLeft + groups.size() * group_width + 40.0 + 140.0;
  double top = std::isfinite(reference_mm) ? reference_mm : 0.0;
  for (const BarGroup& g : groups)
    for (double v : g.values)
      if (std::isfinite(v)) top = std::max(top, v);
  top = top > 0.0 ? 1.1 * top : 1.0;
  auto y = [&](double v) { return kTop + kPlotHeight * (1.0 - v / top); };
  std::ostringstream s;
  s << fmt::format(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="{:.0f}" height="{:.0f}" font-family="sans-serif" font-size="11">)svg",
                   width, kTop + kPlotHeight + kBottom)
    << "\n";
  s << fmt::format(R"svg(<rect x="0" y="0" width="{:.0f}" height="{:.0f}" fill="white"/>)svg", width, kTop + kPlotHeight + kBottom)
    << "\n";
  s << fmt::format(R"svg(<text x="{:.1f}" y="20" font-size="13">{}</text>)svg", kLeft, xml_escape(title)) << "\n";
  for (int k = 0; k <= 4; ++k) {
    const double v = top * k / 4.0;
    s << fmt::format(R"svg(<line x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}" stroke="#ddd"/>)svg", kLeft, y(v),
                     kLeft + groups.size() * group_width, y(v))
      << "\n";
    s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}" text-anchor="end">{:.2f}</text>)svg", kLeft - 4, y(v) + 4, v) << "\n";
  }
  s << fmt::format(R"svg(<text x="14" y="{:.1f}" transform="rotate(-90 14 {:.1f})" text-anchor="middle">mean error (mm)</text>)svg",
                   kTop + kPlotHeight / 2, kTop + kPlotHeight / 2)
    << "\n";
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double gx = kLeft + g * group_width + kGap / 2;
    for (std::size_t k = 0; k < groups[g].values.size() && k < series.size(); ++k) {
      const double v = groups[g].values[k];
      if (!std::isfinite(v)) continue;
      s << fmt::format(R"svg(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="{}"/>)svg", gx + k * kBar, y(v),
                       kBar - 1, kTop + kPlotHeight - y(v), kSeriesColours[k % std::size(kSeriesColours)])
        << "\n";
    }
    const double lx = gx + series.size() * kBar / 2, ly = kTop + kPlotHeight + 8;
    s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}" transform="rotate(60 {:.1f} {:.1f})">{}</text>)svg", lx, ly, lx, ly,
                     xml_escape(groups[g].label))
      << "\n";
  }
  if (std::isfinite(reference_mm)) {
    s << fmt::format(R"svg(<line x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}" stroke="black" stroke-dasharray="5,3"/>)svg", kLeft,
                     y(reference_mm), kLeft + groups.size() * group_width, y(reference_mm))
      << "\n";
  }
  const double legend_x = kLeft + groups.size() * group_width + 20;
  for (std::size_t k = 0; k < series.size(); ++k) {
    s << fmt::format(R"svg(<rect x="{:.1f}" y="{:.1f}" width="10" height="10" fill="{}"/>)svg", legend_x, kTop + 16 * k,
                     kSeriesColours[k % std::size(kSeriesColours)])
      << "\n";
    s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">{}</text>)svg", legend_x + 14, kTop + 16 * k + 9, xml_escape(series[k]))
      << "\n";
  }
  if (std::isfinite(reference_mm))
    s << fmt::format(R"svg(<text x="{:.1f}" y="{:.1f}">- - {}</text>)svg", legend_x, kTop + 16 * series.size() + 9,
                     xml_escape(reference_label))
      << "\n";
  s << "</svg>\n";
  return s.str();
}

}  // namespace twin::diagnosis
