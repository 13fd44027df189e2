#include "sim_hw/lab_reference.h"

#include <algorithm>
#include <memory>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/real_sheet/stage_path.h"
#include "sim_hw/shell_reference.h"
#include "twin/mesh/material_point.h"
#include "twin/mesh/mesh_refinement.h"
#include "twin/model/shell_model.h"
#include "twin/trials/trial_simulation.h"

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

struct IndependentPath {
  real_sheet::SheetMaterial material;
  std::unique_ptr<real_sheet::SheetModel> model;
  real_sheet::PathResult result;
  std::vector<double> ages_s;
};

IndependentPath independent_path(const ReferenceSheet& reference, const twin::Material& truth,
                                 const std::vector<Crease>& creases, double w, double h,
                                 const std::vector<twin::ClampSpec>& clamps,
                                 const std::vector<twin::TrialStage>& stages, const std::vector<twin::Vec2>& marker_uv) {
  namespace rs = real_sheet;
  IndependentPath path;
  path.material = rs::sheet_material_from(truth);
  for (const Crease& c : creases) path.material.creases.push_back({c.point_m, c.direction_rad, c.angle_rad, 0.015});
  const double spacing =
      reference.path_grid_spacing_m > 0 ? reference.path_grid_spacing_m : independent_path_spacing_m(truth);
  path.model = std::make_unique<rs::SheetModel>(rs::Grid(w, h, spacing), path.material, marker_uv);
  const std::vector<rs::PathStage> stage_poses = rs::path_stages(stages);
  for (std::size_t k = 0; k < stages.size(); ++k) {
    // Without creep the age changes nothing; the path solves every stage at age 0 then.
    path.ages_s.push_back(path.material.creep_fraction > 0 ? stage_poses[k].age_s : 0.0);
  }
  rs::PathOptions options;
  options.jaws = reference.jaws;
  path.result = rs::simulate_path(*path.model, clamps, stage_poses, options);
  if (!path.result.usable()) {
    throw std::runtime_error(fmt::format("the independent reference sheet failed at {}", path.result.failure));
  }
  return path;
}

// Stages of the independent sheet on one grid: the model, each stage's equilibrium and holds.
struct IndependentStages {
  std::unique_ptr<real_sheet::SheetModel> model;
  std::vector<twin::VecX> x;
  std::vector<std::vector<real_sheet::JawHold>> holds;
  int iterations = 0;  // of the solves that carried them there
};

// `from`'s stages carried to the graded grid of `spacing` and solved there.
// The stages x (equilibria on `from`, with their jaw holds) solved again on the model `to`,
// each from its carried state, so they stay on their branch.
IndependentStages carry_onto(const ReferenceSheet& reference, const IndependentPath& path,
                             const real_sheet::SheetModel& from, const std::vector<twin::VecX>& x,
                             const std::vector<std::vector<real_sheet::JawHold>>& holds,
                             std::unique_ptr<real_sheet::SheetModel> to) {
  namespace rs = real_sheet;
  IndependentStages out;
  out.model = std::move(to);
  rs::PathOptions options;
  options.jaws = reference.jaws;
  // A stage identical to the one before on `from` (a repeated scan of one pose, at the same age:
  // without creep every age is 0) has the same equilibrium here: no second solve.
  const auto same_holds = [](const std::vector<rs::JawHold>& a, const std::vector<rs::JawHold>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].centre_m != b[i].centre_m || a[i].rotation != b[i].rotation) return false;
    return true;
  };
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (k > 0 && x[k] == x[k - 1] && path.ages_s[k] == path.ages_s[k - 1] && same_holds(holds[k], holds[k - 1])) {
      out.x.push_back(out.x.back());
      out.holds.push_back(holds[k]);
      continue;
    }
    out.model->set_age_s(path.ages_s[k]);
    rs::EquilibriumReport report;
    try {
      out.x.push_back(rs::carry_to_grid(from, x[k], holds[k], *out.model, options, &report));
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("stage {}: {}", k + 1, e.what()));
    }
    out.holds.push_back(holds[k]);  // poses as they were; pads are rebuilt per grid by carry_to_grid
    out.iterations += report.iterations;
  }
  return out;
}

IndependentStages carry_stages(const ReferenceSheet& reference, const IndependentPath& path,
                               const real_sheet::SheetModel& from, const std::vector<twin::VecX>& x,
                               const std::vector<std::vector<real_sheet::JawHold>>& holds, double w, double h,
                               const std::vector<twin::ClampSpec>& clamps, double spacing,
                               const std::vector<twin::Vec2>& marker_uv) {
  namespace rs = real_sheet;
  std::vector<rs::JawSpot> spots;
  for (const twin::ClampSpec& c : clamps) spots.push_back({c.material_point_m, c.grip_radius_m});
  return carry_onto(reference, path, from, x, holds,
                    std::make_unique<rs::SheetModel>(rs::graded_grid(w, h, spots, spacing), path.material, marker_uv));
}

ReferenceStages reference_stages(const ReferenceSheet& reference, const IndependentPath& path,
                                 const real_sheet::SheetModel& model, const std::vector<twin::VecX>& x,
                                 int fine_iterations, const std::vector<twin::Vec2>& marker_uv) {
  ReferenceStages out;
  const real_sheet::Grid& grid = model.grid();
  const real_sheet::Grid& coarse = path.model->grid();
  out.size = grid.node_count();
  for (const twin::VecX& xs : x) {
    out.markers_m.push_back(model.marker_positions(xs));
    std::vector<Vec3> normals;
    for (const twin::Vec2& uv : marker_uv) normals.push_back(model.normal_at(xs, uv));
    out.normals.push_back(std::move(normals));
  }
  out.description = fmt::format(
      "independent plate, {} x {} grid ({:.1f}-{:.1f} mm), path on {} x {} ({:.1f} mm), {} jaws ({} path increments, "
      "{} path iterations, {} fine iterations)",
      grid.nu(), grid.nv(), 1e3 * grid.min_spacing_m(), 1e3 * grid.max_spacing_m(), coarse.nu(), coarse.nv(),
      1e3 * coarse.max_spacing_m(), to_string(reference.jaws), path.result.increments, path.result.iterations,
      fine_iterations);
  return out;
}

// The path's stages on the graded grid of `spacing` (the path's own when not finer).
ReferenceStages independent_stages(const ReferenceSheet& reference, const IndependentPath& path, double w, double h,
                                   const std::vector<twin::ClampSpec>& clamps, double spacing,
                                   const std::vector<twin::Vec2>& marker_uv) {
  if (spacing >= 0.999 * path.model->grid().max_spacing_m()) {
    return reference_stages(reference, path, *path.model, path.result.stages, 0, marker_uv);
  }
  const IndependentStages fine = carry_stages(reference, path, *path.model, path.result.stages, path.result.holds, w,
                                              h, clamps, spacing, marker_uv);
  return reference_stages(reference, path, *fine.model, fine.x, fine.iterations, marker_uv);
}

ReferenceStages independent_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                      const std::vector<Crease>& creases, double w, double h,
                                      const std::vector<twin::ClampSpec>& clamps,
                                      const std::vector<twin::TrialStage>& stages,
                                      const std::vector<twin::Vec2>& marker_uv) {
  const IndependentPath path = independent_path(reference, truth, creases, w, h, clamps, stages, marker_uv);
  const double spacing = reference.grid_spacing_m > 0 ? reference.grid_spacing_m : independent_grid_spacing_m(truth);
  return independent_stages(reference, path, w, h, clamps, spacing, marker_uv);
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
  if (name == "spline_shell") return TruthModel::kSplineShell;
  throw std::invalid_argument(
      fmt::format("{}: '{}' is not a truth model (expected independent, twin or spline_shell)", what, name));
}

std::string to_string(TruthModel model) {
  switch (model) {
    case TruthModel::kTwin: return "twin";
    case TruthModel::kSplineShell: return "spline_shell";
    case TruthModel::kIndependent: break;
  }
  return "independent";
}

real_sheet::JawKind parse_jaw_kind(const std::string& name, const std::string& what) {
  if (name == "rigid") return real_sheet::JawKind::kRigid;
  if (name == "pivot") return real_sheet::JawKind::kPivot;
  throw std::invalid_argument(fmt::format("{}: '{}' is not a kind of jaws (expected rigid or pivot)", what, name));
}

std::string to_string(real_sheet::JawKind kind) { return kind == real_sheet::JawKind::kPivot ? "pivot" : "rigid"; }

bool hidden_under_clamp(const std::vector<twin::ClampSpec>& clamps, const std::vector<twin::ClampPose>& poses,
                        const twin::Vec2& marker_uv_m, double radius_m) {
  for (std::size_t c = 0; c < clamps.size() && c < poses.size(); ++c) {
    if (poses[c].engaged && (marker_uv_m - clamps[c].material_point_m).norm() < radius_m) return true;
  }
  return false;
}

namespace {

double bending_length_m(const twin::Material& m) {
  const double D = std::min(m.bending_rigidity_u_Nm, m.bending_rigidity_v_Nm);
  return std::cbrt(D / (m.surface_density_kg_m2 * twin::kStandardGravity));
}

}  // namespace

double independent_grid_spacing_m(const twin::Material& m) { return std::min(0.02, 0.3 * bending_length_m(m)); }

double independent_path_spacing_m(const twin::Material& m) { return std::min(0.03, 0.5 * bending_length_m(m)); }

nlohmann::json truth_error_json(const std::vector<TruthError>& errors, const std::vector<twin::TrialStage>& stages) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t s = 0; s < errors.size() && s < stages.size(); ++s) {
    const TruthError& e = errors[s];
    out.push_back({{"stage", stages[s].id},
                   {"finest_change_mean_m", e.finest_change_mean_m},
                   {"finest_change_max_m", e.finest_change_max_m},
                   {"one_branch", e.one_branch},
                   {"order", e.order ? nlohmann::json(*e.order) : nlohmann::json()},
                   {"estimated_error_m", e.estimated_m ? nlohmann::json(*e.estimated_m) : nlohmann::json()},
                   {"summary", e.text}});
  }
  return out;
}

double default_shell_span_m(const twin::Material& m) { return std::min(0.02, bending_length_m(m) / 3.0); }

std::vector<ReferenceStages> independent_refinement(const ReferenceSheet& reference, const twin::Material& truth,
                                                    const std::vector<Crease>& creases, double width_m,
                                                    double height_m, const std::vector<twin::ClampSpec>& clamps,
                                                    const std::vector<twin::TrialStage>& stages,
                                                    const std::vector<twin::Vec2>& marker_uv_m,
                                                    const std::vector<double>& spacings_m, double bending_change) {
  const IndependentPath path =
      independent_path(reference, truth, creases, width_m, height_m, clamps, stages, marker_uv_m);
  // Each grid carries the stages from the one before (coarse to fine), so every grid solves
  // them on the branch its neighbour found.
  std::vector<double> order = spacings_m;
  std::sort(order.begin(), order.end(), std::greater<>());
  std::vector<ReferenceStages> out;
  IndependentStages last;
  for (const double h : order) {
    if (h >= 0.999 * path.model->grid().max_spacing_m()) {
      out.push_back(reference_stages(reference, path, *path.model, path.result.stages, 0, marker_uv_m));
      continue;
    }
    IndependentStages next =
        last.model ? carry_stages(reference, path, *last.model, last.x, last.holds, width_m, height_m, clamps, h, marker_uv_m)
                   : carry_stages(reference, path, *path.model, path.result.stages, path.result.holds, width_m,
                                  height_m, clamps, h, marker_uv_m);
    out.push_back(reference_stages(reference, path, *next.model, next.x, next.iterations, marker_uv_m));
    last = std::move(next);
  }
  if (bending_change != 0.0 && last.model) {
    real_sheet::SheetMaterial changed = path.material;
    for (double* D : {&changed.D11_Nm, &changed.D22_Nm, &changed.D12_Nm, &changed.D66_Nm}) *D *= 1.0 + bending_change;
    const IndependentStages stiffer =
        carry_onto(reference, path, *last.model, last.x, last.holds,
                   std::make_unique<real_sheet::SheetModel>(last.model->grid(), changed, marker_uv_m));
    out.push_back(reference_stages(reference, path, *stiffer.model, stiffer.x, stiffer.iterations, marker_uv_m));
  }
  return out;
}


ReferenceStages simulate_reference(const ReferenceSheet& reference, const twin::Material& truth,
                                   const std::vector<Crease>& creases, double width_m, double height_m,
                                   const std::vector<twin::ClampSpec>& clamps,
                                   const std::vector<twin::TrialStage>& stages,
                                   const std::vector<twin::Vec2>& marker_uv_m) {
  switch (reference.model) {
    case TruthModel::kTwin:
      return twin_reference(reference, truth, creases, width_m, height_m, clamps, stages, marker_uv_m);
    case TruthModel::kSplineShell:
      return shell_reference(reference, truth, creases, width_m, height_m, clamps, stages, marker_uv_m);
    case TruthModel::kIndependent: break;
  }
  return independent_reference(reference, truth, creases, width_m, height_m, clamps, stages, marker_uv_m);
}

}  // namespace sim_hw
