#include "cell/grasp_planning/plan_table.h"

#include <algorithm>

#include <fmt/format.h>

namespace cell {

std::string candidate_table(const PlannerResult& r, int rows) {
  std::string out = fmt::format("{:>3} {:<7} {:>6} {:>6} {:>8} {:>10} {:>9} {:>6} {:<6}  {}\n", "#", "kind",
                                "inset", "slack", "sag_m", "bend_r_m", "overturn", "mesh", "ok", "grasps (gripper u,v m)");
  const int n = std::min(rows, static_cast<int>(r.ranked.size()));
  for (int i = 0; i < n; ++i) {
    const CandidateResult& c = r.ranked[i];
    std::string grasps;
    for (const twin::Grasp& g : c.grasps) {
      grasps += fmt::format("{}{} {:.2f},{:.2f}", grasps.empty() ? "" : "  ", g.gripper,
                            g.clamp.material_point_m.x(), g.clamp.material_point_m.y());
    }
    const HangEvaluation* e = !c.unreachable.empty() ? nullptr : c.target ? &*c.target : &c.screening;
    const int triangles = c.target ? r.target_triangles : r.screening_triangles;
    if (e && e->solved) {
      out += fmt::format("{:>3} {:<7} {:>6.2f} {:>5.0f}% {:>8.3f} {:>10.3f} {:>8.1f}% {:>6} {:<6}  {}\n", i + 1,
                         c.candidate.kind, c.candidate.inset_m, 100.0 * c.candidate.slack, e->metrics.sag_m,
                         e->metrics.min_bend_radius_m, 100.0 * e->metrics.overturned_fraction, triangles,
                         e->feasible ? "yes" : "no", grasps);
    } else {
      out += fmt::format("{:>3} {:<7} {:>6.2f} {:>5.0f}% {:>8} {:>10} {:>9} {:>6} {:<6}  {}  ({})\n", i + 1,
                         c.candidate.kind, c.candidate.inset_m, 100.0 * c.candidate.slack, "-", "-", "-",
                         triangles, "no", grasps, e ? e->reason : c.unreachable);
    }
  }
  return out;
}

}  // namespace cell
