#include "sim_hw/shell_reference.h"

#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/spline_shell/branch_label.h"
#include "sim_hw/spline_shell/jaw_grip.h"
#include "sim_hw/spline_shell/refinement_estimate.h"
#include "sim_hw/spline_shell/shell_path.h"

namespace sim_hw {

ReferenceStages shell_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                const std::vector<Crease>& creases, double w, double h,
                                const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::TrialStage>& stages,
                                const std::vector<twin::Vec2>& marker_uv) {
  namespace ss = spline_shell;
  namespace rs = real_sheet;
  if (reference.jaws != rs::JawKind::kRigid) {
    throw std::invalid_argument("scanner lab: the spline shell reference has rigid square jaws only (pivot jaws: --truth-model independent)");
  }
  if (reference.shell_levels < 0) throw std::invalid_argument("scanner lab: shell levels must be 0 or more");
  rs::SheetMaterial material = rs::sheet_material_from(truth);
  for (const Crease& c : creases) material.creases.push_back({c.point_m, c.direction_rad, c.angle_rad, 0.015});
  const std::vector<ss::SquareJaw> jaws = ss::clamp_jaws(clamps, w, h);
  const std::vector<rs::PathStage> path_stages = rs::path_stages(stages);
  const double ring_m = ss::jaw_grip(material).knot_extension_m();  // wide jaws' ring edges
  const double span_m = reference.shell_span_m > 0 ? reference.shell_span_m : default_shell_span_m(truth);
  const double jaw_span_m = reference.shell_jaw_span_m > 0 ? reference.shell_jaw_span_m : 0.5 * span_m;
  ss::KnotVector ku = ss::jaw_knots(reference.shell_degree, w, 0, jaws, span_m, jaw_span_m, ring_m);
  ss::KnotVector kv = ss::jaw_knots(reference.shell_degree, h, 1, jaws, span_m, jaw_span_m, ring_m);
  auto model = std::make_unique<ss::ShellModel>(ss::SplinePatch(ku, kv), material, marker_uv);
  const ss::ShellPathResult path = ss::follow_path(*model, jaws, path_stages);
  if (!path.usable()) throw std::runtime_error("the spline shell reference failed at " + path.failure);
  std::vector<ss::VecX> x = path.stages;
  std::vector<ss::ShellHolds> holds = path.holds;
  int carried_iterations = 0, relaxation_iterations = 0;
  // Per level, per stage: the markers and the branch label, for the truth's own error.
  std::vector<std::vector<std::vector<twin::Vec3>>> level_markers;
  std::vector<std::vector<ss::BranchLabel>> level_labels;
  const auto record = [&](const ss::ShellModel& m) {
    level_markers.emplace_back();
    level_labels.emplace_back();
    for (const ss::VecX& xs : x) {
      level_markers.back().push_back(m.marker_positions(xs));
      level_labels.back().push_back(ss::branch_label(m.patch(), xs));
    }
  };
  if (reference.shell_levels > 0) record(*model);
  for (int level = 1; level <= reference.shell_levels; ++level) {
    ku = ss::refined(ku), kv = ss::refined(kv);
    auto finer = std::make_unique<ss::ShellModel>(ss::SplinePatch(ku, kv), material, marker_uv);
    ss::CarriedPath carried;
    try {
      carried = ss::carry_path(*model, x, holds, *finer, jaws, path_stages);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("the spline shell reference failed at level {}, {}", level, e.what()));
    }
    carried_iterations += carried.iterations;
    relaxation_iterations += carried.relaxation_iterations;
    x = std::move(carried.stages);
    holds = std::move(carried.holds);
    model = std::move(finer);
    record(*model);
  }
  ReferenceStages out;
  out.size = model->patch().control_count();
  for (std::size_t s = 0; s < x.size() && level_markers.size() >= 2; ++s) {
    std::vector<bool> counted;  // what a scan sees
    for (const twin::Vec2& uv : marker_uv) {
      counted.push_back(!hidden_under_clamp(clamps, stages[s].poses, uv, reference.error_hidden_radius_m));
    }
    std::vector<std::vector<twin::Vec3>> markers;
    std::vector<ss::BranchLabel> labels;
    for (std::size_t l = 0; l < level_markers.size(); ++l) {
      markers.push_back(level_markers[l][s]);
      labels.push_back(level_labels[l][s]);
    }
    const ss::StageRefinement r = ss::stage_refinement(markers, labels, counted);
    TruthError e;
    e.finest_change_mean_m = r.finest().mean_m;
    e.finest_change_max_m = r.finest().max_m;
    e.one_branch = r.finest().same_branch;
    e.order = r.order;
    e.estimated_m = r.finest_error_m;
    e.text = ss::summary_text(r);
    out.truth_error.push_back(std::move(e));
  }
  for (const ss::VecX& xs : x) {
    out.markers_m.push_back(model->marker_positions(xs));
    std::vector<twin::Vec3> normals;
    for (const twin::Vec2& uv : marker_uv) normals.push_back(model->patch().normal(xs, uv));
    out.normals.push_back(std::move(normals));
  }
  out.description = fmt::format(
      "spline shell (Kirchhoff-Love, degree {}), level {}: {} x {} controls ({:.1f}-{:.1f} mm spans at level 0, halved "
      "per level), path on level 0 ({} increments, {} iterations), {} L-BFGS and {} Newton iterations carrying it up",
      reference.shell_degree, reference.shell_levels, model->patch().nu(), model->patch().nv(),
      1e3 * jaw_span_m, 1e3 * span_m, path.increments, path.iterations,
      relaxation_iterations, carried_iterations);
  return out;
}

}  // namespace sim_hw
