#include "sim_hw/lab_reference.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/real_sheet/stage_path.h"
#include "twin/material_point.h"
#include "twin/mesh_refinement.h"
#include "twin/shell_model.h"
#include "twin/trial_simulation.h"

namespace sim_hw {
namespace {

using twin::Vec3;

ReferenceStages twin_reference(const ReferenceSheet& reference, const twin::Material& truth,
                               const std::vector<Crease>& creases, double w, double h,
                               const std::vector<twin::ClampSpec>& clamp_specs,
                               const std::vector<twin::TrialStage>& stages, const std::vector<twin::Vec2>& marker_uv) {
  twin::ShellModel model(twin_reference_mesh(reference, w, h, clamp_specs), truth);
  const twin::MaterialPointMap markers(model.mesh(), marker_uv);
  model.set_marker_points(markers);
  for (const Crease& crease : creases) {
    if (apply_crease(model, crease) == 0) throw std::runtime_error("scanner lab: a crease line misses the sheet");
  }
  const twin::ClampSet clamps(model.mesh(), clamp_specs);
  model.set_clamps_of_material_effects(clamps);  // jaws that grip wider, or slip
  const twin::TrialSimulation simulated = twin::simulate_stages(model, clamps, stages);
  if (!simulated.usable()) throw std::runtime_error(fmt::format("the twin reference sheet failed at {}", simulated.failure));
  ReferenceStages out;
  out.size = model.mesh().triangle_count();
  out.description = fmt::format("twin shell model, {} triangles", out.size);
  for (const twin::StageSimulation& s : simulated.stages) {
    out.markers_m.push_back(markers.positions(s.x));
    std::vector<Vec3> normals;
    for (int m = 0; m < markers.size(); ++m) {
      const twin::MaterialPointLocation& at = markers.location(m);
      const Vec3 a = s.x.segment<3>(3 * at.vertices[0]), b = s.x.segment<3>(3 * at.vertices[1]),
                 c = s.x.segment<3>(3 * at.vertices[2]);
      normals.push_back((b - a).cross(c - a).normalized());
    }
    out.normals.push_back(std::move(normals));
  }
  return out;
}

ReferenceStages independent_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                      const std::vector<Crease>& creases, double w, double h,
                                      const std::vector<twin::ClampSpec>& clamps,
                                      const std::vector<twin::TrialStage>& stages,
                                      const std::vector<twin::Vec2>& marker_uv) {
  namespace rs = real_sheet;
  rs::SheetMaterial material = rs::sheet_material_from(truth);
  for (const Crease& c : creases) material.creases.push_back({c.point_m, c.direction_rad, c.angle_rad, 0.015});
  const double spacing = reference.grid_spacing_m > 0 ? reference.grid_spacing_m : independent_grid_spacing_m(truth);
  rs::SheetModel model(rs::Grid(w, h, spacing), material, marker_uv);
  std::vector<rs::PathStage> path(stages.size());
  for (std::size_t k = 0; k < stages.size(); ++k) {
    path[k].poses = stages[k].poses;
    if (stages[k].time_s && stages[k].clamps_moved_at_s) path[k].age_s = *stages[k].time_s - *stages[k].clamps_moved_at_s;
  }
  rs::PathOptions options;
  options.jaws = reference.jaws;
  const rs::PathResult result = rs::simulate_path(model, clamps, path, options);
  if (!result.usable()) throw std::runtime_error(fmt::format("the independent reference sheet failed at {}", result.failure));
  ReferenceStages out;
  const rs::Grid& grid = model.grid();
  out.size = grid.node_count();
  out.description = fmt::format("independent plate, {} x {} grid ({:.1f} x {:.1f} mm), {} jaws", grid.nu(), grid.nv(),
                                1e3 * grid.du(), 1e3 * grid.dv(), to_string(reference.jaws));
  for (const twin::VecX& x : result.stages) {
    out.markers_m.push_back(model.marker_positions(x));
    std::vector<Vec3> normals;
    for (const twin::Vec2& uv : marker_uv) normals.push_back(model.normal_at(x, uv));
    out.normals.push_back(std::move(normals));
  }
  return out;
}

}  // namespace

twin::SheetMesh twin_reference_mesh(const ReferenceSheet& reference, double w, double h,
                                    const std::vector<twin::ClampSpec>& clamps) {
  if (reference.resolve_jaws && !reference.clamp_refinement_radii_m.empty()) {
    throw std::invalid_argument("scanner lab: give reference clamp refinement radii or resolve the jaws, not both");
  }
  const twin::SheetMesh uniform =
      twin::make_rectangular_sheet(w, h, twin::edge_length_for_triangle_count(w, h, reference.triangles));
  return reference.resolve_jaws ? twin::refine_to_resolve_jaws(uniform, clamps)
                                : twin::refine_near_clamps(uniform, clamps, reference.clamp_refinement_radii_m);
}

TruthModel parse_truth_model(const std::string& name, const std::string& what) {
  if (name == "independent") return TruthModel::kIndependent;
  if (name == "twin") return TruthModel::kTwin;
  throw std::invalid_argument(fmt::format("{}: '{}' is not a truth model (expected independent or twin)", what, name));
}

std::string to_string(TruthModel model) { return model == TruthModel::kTwin ? "twin" : "independent"; }

real_sheet::JawKind parse_jaw_kind(const std::string& name, const std::string& what) {
  if (name == "rigid") return real_sheet::JawKind::kRigid;
  if (name == "pivot") return real_sheet::JawKind::kPivot;
  throw std::invalid_argument(fmt::format("{}: '{}' is not a kind of jaws (expected rigid or pivot)", what, name));
}

std::string to_string(real_sheet::JawKind kind) { return kind == real_sheet::JawKind::kPivot ? "pivot" : "rigid"; }

double independent_grid_spacing_m(const twin::Material& m) {
  const double D = std::min(m.bending_rigidity_u_Nm, m.bending_rigidity_v_Nm);
  const double bending_length_m = std::cbrt(D / (m.surface_density_kg_m2 * twin::kStandardGravity));
  return std::min(0.01, 0.1 * bending_length_m);
}

ReferenceStages simulate_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                   const std::vector<Crease>& creases, double width_m, double height_m,
                                   const std::vector<twin::ClampSpec>& clamps,
                                   const std::vector<twin::TrialStage>& stages,
                                   const std::vector<twin::Vec2>& marker_uv_m) {
  return reference.model == TruthModel::kTwin
             ? twin_reference(reference, truth, creases, width_m, height_m, clamps, stages, marker_uv_m)
             : independent_reference(reference, truth, creases, width_m, height_m, clamps, stages, marker_uv_m);
}

}  // namespace sim_hw
