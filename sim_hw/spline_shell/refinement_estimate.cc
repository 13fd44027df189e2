#include "sim_hw/spline_shell/refinement_estimate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::spline_shell {

StageRefinement stage_refinement(const std::vector<std::vector<Vec3>>& markers, const std::vector<BranchLabel>& labels,
                                 const std::vector<bool>& counted, const BranchMatch& match) {
  if (markers.size() < 2 || labels.size() != markers.size()) {
    throw std::invalid_argument("spline shell: a refinement estimate needs two levels or more, with a label each");
  }
  for (const auto& level : markers) {
    if (level.size() != counted.size()) {
      throw std::invalid_argument("spline shell: a refinement estimate needs every level's markers, one flag each");
    }
  }
  StageRefinement r;
  for (std::size_t l = 0; l + 1 < markers.size(); ++l) {
    LevelChange c;
    int n = 0;
    for (std::size_t m = 0; m < counted.size(); ++m) {
      if (!counted[m]) continue;
      const double d = (markers[l][m] - markers[l + 1][m]).norm();
      if (d > c.max_m || c.max_marker < 0) c.max_m = d, c.max_marker = static_cast<int>(m);
      c.mean_m += d, ++n;
    }
    c.mean_m /= std::max(n, 1);
    c.same_branch = same_branch(labels[l], labels[l + 1], match.tolerance_m, match.significant_fold_m2, &c.why);
    r.changes.push_back(std::move(c));
  }
  if (r.changes.size() < 2) {
    r.no_order = "one change only";
    return r;
  }
  const LevelChange& a = r.changes[r.changes.size() - 2];
  const LevelChange& b = r.changes.back();
  if (!a.same_branch || !b.same_branch) {
    r.no_order = "the two finest comparisons are not on one branch";
    return r;
  }
  const double order = std::log2(a.mean_m / b.mean_m);
  if (!(order > 0.2)) {
    r.no_order = fmt::format("order {:.2f}, below 0.2", order);
    return r;
  }
  r.order = order;
  r.finest_error_m = b.mean_m / (std::pow(2.0, order) - 1.0);
  return r;
}

std::string change_text(int level, const LevelChange& c) {
  return c.same_branch ? fmt::format("{}->{} {:.3f} / {:.3f} mm", level, level + 1, 1e3 * c.mean_m, 1e3 * c.max_m)
                       : fmt::format("{}->{} BRANCH FLIP ({}; markers {:.1f} / {:.1f} mm)", level, level + 1, c.why,
                                     1e3 * c.mean_m, 1e3 * c.max_m);
}

std::string estimate_text(const StageRefinement& r) {
  if (!r.estimated()) return "no order: " + r.no_order;
  return fmt::format("order {:.2f}, finest error {:.3f} mm (GCI {:.3f})", *r.order, 1e3 * *r.finest_error_m,
                     1.25e3 * *r.finest_error_m);
}

std::string summary_text(const StageRefinement& r) {
  std::string text;
  for (std::size_t l = 0; l < r.changes.size(); ++l) text += (l ? "  " : "") + change_text(static_cast<int>(l), r.changes[l]);
  if (r.changes.size() >= 2) text += "  | " + estimate_text(r);
  return text;
}

}  // namespace sim_hw::spline_shell
