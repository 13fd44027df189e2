#include "twin/diagnosis/model_form.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <fmt/format.h>

namespace twin::diagnosis {
namespace {

constexpr int kRegionRows = 3, kRegionCols = 3;

int cell_of(double value, double lo, double hi, int cells) {
  if (!(hi > lo)) return 0;
  return std::clamp(static_cast<int>((value - lo) / (hi - lo) * cells), 0, cells - 1);
}

}  // namespace

ModelFormLocation locate_model_form(const ResidualField& field, double threshold_m) {
  ModelFormLocation out;
  out.threshold_m = threshold_m;
  // Sums of squares per stage and per (trial, row, col).
  std::vector<double> stage_ss(field.stages.size(), 0.0);
  std::vector<int> stage_n(field.stages.size(), 0);
  std::map<std::tuple<int, int, int>, std::pair<double, int>> region;
  for (const ResidualSample& s : field.samples) {
    const double ss = s.residual_m.squaredNorm();
    stage_ss[s.stage] += ss;
    ++stage_n[s.stage];
    const FieldTrial& t = field.trials[s.trial];
    const int row = cell_of(s.uv_m.y(), t.sheet_min_uv_m.y(), t.sheet_max_uv_m.y(), kRegionRows);
    const int col = cell_of(s.uv_m.x(), t.sheet_min_uv_m.x(), t.sheet_max_uv_m.x(), kRegionCols);
    auto& r = region[{s.trial, row, col}];
    r.first += ss;
    ++r.second;
  }
  for (std::size_t i = 0; i < field.stages.size(); ++i) {
    if (stage_n[i] == 0) continue;
    const double rms = std::sqrt(stage_ss[i] / (3.0 * stage_n[i]));
    if (rms > threshold_m) out.stages.push_back({field.stages[i].label, rms, stage_n[i]});
  }
  for (const auto& [key, sum] : region) {
    const auto [trial, row, col] = key;
    const double rms = std::sqrt(sum.first / (3.0 * sum.second));
    if (!(rms > threshold_m)) continue;
    const FieldTrial& t = field.trials[trial];
    const Vec2 size = t.sheet_max_uv_m - t.sheet_min_uv_m;
    MisfitRegion r;
    r.trial = t.name;
    r.row = row;
    r.col = col;
    r.min_uv_m = t.sheet_min_uv_m + Vec2(size.x() * col / kRegionCols, size.y() * row / kRegionRows);
    r.max_uv_m = t.sheet_min_uv_m + Vec2(size.x() * (col + 1) / kRegionCols, size.y() * (row + 1) / kRegionRows);
    r.rms_m = rms;
    r.samples = sum.second;
    out.regions.push_back(r);
  }
  std::sort(out.stages.begin(), out.stages.end(), [](const auto& a, const auto& b) { return a.rms_m > b.rms_m; });
  std::sort(out.regions.begin(), out.regions.end(), [](const auto& a, const auto& b) { return a.rms_m > b.rms_m; });
  return out;
}

std::string describe(const ModelFormLocation& location, int most) {
  if (location.stages.empty() && location.regions.empty()) {
    return fmt::format("no stage and no ninth of a sheet is beyond {:.3f} mm RMS on its own: the misfit is spread "
                       "over the whole sheet",
                       1e3 * location.threshold_m);
  }
  std::string text = fmt::format("beyond {:.3f} mm RMS: ", 1e3 * location.threshold_m);
  if (!location.stages.empty()) {
    text += fmt::format("{} stage(s), worst ", location.stages.size());
    for (int i = 0; i < std::min<int>(most, static_cast<int>(location.stages.size())); ++i) {
      text += fmt::format("{}{} ({:.2f} mm)", i ? ", " : "", location.stages[i].label, 1e3 * location.stages[i].rms_m);
    }
  } else {
    text += "no stage on its own";
  }
  text += "; ";
  if (!location.regions.empty()) {
    text += fmt::format("{} region(s) of the sheet, worst ", location.regions.size());
    for (int i = 0; i < std::min<int>(most, static_cast<int>(location.regions.size())); ++i) {
      const MisfitRegion& r = location.regions[i];
      text += fmt::format("{}u {:.2f}-{:.2f} m, v {:.2f}-{:.2f} m of {} ({:.2f} mm)", i ? ", " : "", r.min_uv_m.x(),
                          r.max_uv_m.x(), r.min_uv_m.y(), r.max_uv_m.y(), r.trial, 1e3 * r.rms_m);
    }
  } else {
    text += "no region on its own";
  }
  return text;
}

}  // namespace twin::diagnosis
