#include "sim_hw/shell_reference.h"

#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/spline_shell/shell_path.h"

namespace sim_hw {

ReferenceStages shell_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                const std::vector<Crease>& creases, double w, double h,
                                const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::TrialStage>& stages,
                                const std::vector<twin::Vec2>& marker_uv) {
  namespace ss = spline_shell;
  namespace rs = real_sheet;
  if (reference.jaws != rs::JawKind::kRigid) {
    throw std::invalid_argument("scanner lab: the spline shell reference has rigid square jaws only (not pivot)");
  }
  if (reference.shell_levels < 0) throw std::invalid_argument("scanner lab: shell levels must be 0 or more");
  rs::SheetMaterial material = rs::sheet_material_from(truth);
  for (const Crease& c : creases) material.creases.push_back({c.point_m, c.direction_rad, c.angle_rad, 0.015});
  const std::vector<ss::SquareJaw> jaws = ss::clamp_jaws(clamps, w, h);
  const std::vector<rs::PathStage> path_stages = rs::path_stages(stages);
  ss::KnotVector ku = ss::jaw_knots(reference.shell_degree, w, 0, jaws, reference.shell_span_m, reference.shell_jaw_span_m);
  ss::KnotVector kv = ss::jaw_knots(reference.shell_degree, h, 1, jaws, reference.shell_span_m, reference.shell_jaw_span_m);
  auto model = std::make_unique<ss::ShellModel>(ss::SplinePatch(ku, kv), material, marker_uv);
  const ss::ShellPathResult path = ss::follow_path(*model, jaws, path_stages);
  if (!path.usable()) throw std::runtime_error("the spline shell reference failed at " + path.failure);
  std::vector<ss::VecX> x = path.stages;
  std::vector<ss::ShellHolds> holds = path.holds;
  int carried_iterations = 0;
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
    x = std::move(carried.stages);
    holds = std::move(carried.holds);
    model = std::move(finer);
  }
  ReferenceStages out;
  out.size = model->patch().control_count();
  for (const ss::VecX& xs : x) {
    out.markers_m.push_back(model->marker_positions(xs));
    std::vector<twin::Vec3> normals;
    for (const twin::Vec2& uv : marker_uv) normals.push_back(model->patch().normal(xs, uv));
    out.normals.push_back(std::move(normals));
  }
  out.description = fmt::format(
      "spline shell (Kirchhoff-Love, degree {}), level {}: {} x {} controls ({:.1f}-{:.1f} mm spans at level 0, halved "
      "per level), path on level 0 ({} increments, {} iterations), {} iterations carrying it up",
      reference.shell_degree, reference.shell_levels, model->patch().nu(), model->patch().nv(),
      1e3 * reference.shell_jaw_span_m, 1e3 * reference.shell_span_m, path.increments, path.iterations,
      carried_iterations);
  return out;
}

}  // namespace sim_hw
