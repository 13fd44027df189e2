#include "twin/trials/discretisation_check.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace twin {

DiscretisationCheck check_discretisation(const std::vector<TrialEvaluator*>& trials, const TwinMeshSpec& mesh,
                                         const Material& material,
                                         const std::vector<MaterialParameter>& parameters) {
  DiscretisationCheck out;
  TwinMeshSpec finer = mesh;
  finer.triangles = 2 * mesh.triangles;
  double moved_sq = 0.0, residual_sq = 0.0;
  long moved_count = 0, residual_count = 0;
  std::vector<double> pattern, coarse_residual;
  bool stacked_alike = true;
  for (TrialEvaluator* coarse : trials) {
    TrialEvaluator fine(coarse->trial(), finer, material);  // the trial as read, not read again
    out.triangles = coarse->model().mesh().triangle_count();
    out.finer_triangles = fine.model().mesh().triangle_count();
    // A sheet given as a mesh file is taken as it is, whatever the triangle count asked: there is
    // no finer twin, and the "pattern" of two equal twins is round-off, whose coefficient in the
    // residual is anything (seen: -4e10 on a cell's observed trial).
    if (out.finer_triangles <= out.triangles) {
      out.failure = fmt::format("{}: not measured: the sheet is the mesh file {} ({} triangles), which has no finer twin",
                                coarse->trial().directory, coarse->trial().sheet.mesh_file, out.triangles);
      return out;
    }
    const TrialFit at_coarse = coarse->evaluate(material, parameters);
    const TrialFit at_fine = fine.evaluate(material, parameters);
    if (!at_coarse.usable() || !at_fine.usable()) {
      out.failure = fmt::format("{}: {}", coarse->trial().directory, at_coarse.usable() ? at_fine.failure : at_coarse.failure);
      return out;
    }
    for (std::size_t s = 0; s < at_coarse.stages.size() && s < at_fine.stages.size(); ++s) {
      const auto& p = at_coarse.stages[s].predicted_markers_m;
      const auto& q = at_fine.stages[s].predicted_markers_m;
      for (std::size_t i = 0; i < p.size() && i < q.size(); ++i) {
        const double d = (p[i] - q[i]).norm();
        moved_sq += d * d;
        out.max_m = std::max(out.max_m, d);
        ++moved_count;
      }
    }
    residual_sq += at_fine.sum_squares_m2;
    residual_count += at_fine.residual_count;
    stacked_alike = stacked_alike && at_fine.residuals_m.size() == at_coarse.residuals_m.size();
    if (stacked_alike) {
      for (Eigen::Index i = 0; i < at_fine.residuals_m.size(); ++i) {
        pattern.push_back(at_coarse.residuals_m(i) - at_fine.residuals_m(i));
        coarse_residual.push_back(at_coarse.residuals_m(i));
      }
    }
  }
  if (stacked_alike && !pattern.empty()) {
    const auto size = static_cast<Eigen::Index>(pattern.size());
    out.error_pattern_m = Eigen::Map<const VecX>(pattern.data(), size);
    const Eigen::Map<const VecX> r(coarse_residual.data(), size);
    const double pattern_sq = out.error_pattern_m.squaredNorm();
    if (pattern_sq > 0.0) {
      out.pattern_in_residual = r.dot(out.error_pattern_m) / pattern_sq;
      out.error_in_residual_rms_m =
          std::max(0.0, out.pattern_in_residual) * std::sqrt(pattern_sq / static_cast<double>(size));
    }
  }
  if (moved_count == 0) {
    out.failure = "no marker stage to compare";
    return out;
  }
  out.rms_m = std::sqrt(moved_sq / (3.0 * static_cast<double>(moved_count)));
  out.finer_residual_rms_m = residual_count > 0 ? std::sqrt(residual_sq / static_cast<double>(residual_count)) : 0.0;
  return out;
}

std::string describe(const DiscretisationCheck& c, const std::string& where) {
  if (!c.usable()) return "check failed: " + c.failure;
  return fmt::format("markers move {:.3f} mm RMS per coordinate (max {:.2f} mm) from {} to {} triangles {}; residual "
                     "RMS per coordinate there {:.3f} mm; the residual holds {:.2f} of that change ({:.3f} mm RMS "
                     "of discretisation error)",
                     1e3 * c.rms_m, 1e3 * c.max_m, c.triangles, c.finer_triangles, where, 1e3 * c.finer_residual_rms_m,
                     c.pattern_in_residual, 1e3 * c.error_in_residual_rms_m);
}

}  // namespace twin
