#include "twin/diagnosis/cycle_residuals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/mesh/material_point.h"

namespace twin::diagnosis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_cycle(const SheetCycle& c, int vertices) {
  const auto n3 = static_cast<Eigen::Index>(3 * vertices);
  if (c.observed_m.size() != n3 || c.predicted_m.size() != n3) {
    throw std::invalid_argument(fmt::format("cycle {}: expected {} vertices (the twin's mesh) in the observed and the "
                                            "predicted sheet, got {} and {}",
                                            c.cycle_id, vertices, c.observed_m.size() / 3, c.predicted_m.size() / 3));
  }
  if (!c.seen.empty() && c.seen.size() != static_cast<std::size_t>(vertices)) {
    throw std::invalid_argument(fmt::format("cycle {}: expected {} observed-vertex flags, got {}", c.cycle_id, vertices,
                                            c.seen.size()));
  }
  if (!c.predicted_m.allFinite()) throw std::invalid_argument(fmt::format("cycle {}: non-finite predicted sheet", c.cycle_id));
}

}  // namespace

std::vector<std::size_t> spread_cycles(std::size_t cycles, std::size_t count) {
  std::vector<std::size_t> out;
  if (cycles == 0 || count == 0) return out;
  if (count == 1) return {0};
  if (count >= cycles) {
    for (std::size_t k = 0; k < cycles; ++k) out.push_back(k);
    return out;
  }
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = static_cast<std::size_t>(
        std::llround(static_cast<double>(k) * static_cast<double>(cycles - 1) / static_cast<double>(count - 1)));
    if (out.empty() || i > out.back()) out.push_back(i);
  }
  return out;
}

void add_cycle_residuals(ResidualField& field, const SheetMesh& mesh, const std::vector<ClampSpec>& clamps,
                         const std::vector<SheetCycle>& cycles, const std::string& name,
                         const std::vector<std::size_t>& selected) {
  for (std::size_t k = 0; k < selected.size(); ++k) {
    if (selected[k] >= cycles.size() || (k > 0 && selected[k] <= selected[k - 1])) {
      throw std::invalid_argument(fmt::format("cycle residuals: selected cycle indices must ascend below {}", cycles.size()));
    }
  }
  const int n = mesh.vertex_count();
  for (const SheetCycle& c : cycles) check_cycle(c, n);
  FieldTrial ft = field_trial_on(mesh, name);
  ft.marker_count = n;
  const int trial_index = static_cast<int>(field.trials.size());
  field.trials.push_back(ft);

  std::vector<Vec2> grasp_uv;
  for (const ClampSpec& c : clamps) grasp_uv.push_back(c.material_point_m);
  const MaterialPointMap grasp_points(mesh, grasp_uv);
  double base_height_m = kNaN;
  double last_move_s = kNaN;
  std::vector<Vec3> previous_grasps;
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    const SheetCycle& c = cycles[k];
    const std::vector<Vec3> grasps = grasp_points.positions(c.predicted_m);
    if (k == 0 && !grasps.empty()) {
      base_height_m = 0.0;
      for (const Vec3& g : grasps) base_height_m += g.z();
      base_height_m /= static_cast<double>(grasps.size());
    }
    for (std::size_t g = 0; g < previous_grasps.size() && g < grasps.size(); ++g) {
      if ((grasps[g] - previous_grasps[g]).norm() > kClampMoveM) last_move_s = c.time_s;
    }
    previous_grasps = grasps;
    if (!selected.empty() && !std::binary_search(selected.begin(), selected.end(), k)) continue;

    FieldStage fs;
    fs.trial = trial_index;
    fs.trial_stage = static_cast<int>(k);
    fs.id = std::to_string(c.cycle_id);
    fs.label = name + "/" + fs.id;
    fs.age_s = c.time_s - last_move_s;  // NaN until a move was seen
    double top = -std::numeric_limits<double>::infinity();
    for (const Vec3& g : grasps) top = std::max(top, g.z());
    fs.load_m = grasps.empty() ? 0.0 : top - base_height_m;
    const int stage_index = static_cast<int>(field.stages.size());
    const std::vector<Vec3> normals = vertex_normals(mesh, c.predicted_m);
    const std::vector<double> curvature = vertex_curvatures_1_m(mesh, c.predicted_m);
    double error_sum = 0.0;
    for (int v = 0; v < n; ++v) {
      if (!c.seen.empty() && !c.seen[v]) continue;
      const Vec3 observed = c.observed_m.segment<3>(3 * v);
      if (!observed.allFinite()) {
        throw std::invalid_argument(fmt::format("cycle {}: vertex {} is flagged observed but not finite", c.cycle_id, v));
      }
      ResidualSample s;
      s.trial = trial_index;
      s.stage = stage_index;
      s.marker = v;
      s.uv_m = mesh.rest_uv[v];
      s.observed_m = observed;
      s.residual_m = observed - c.predicted_m.segment<3>(3 * v);
      s.normal = normals[v];
      s.normal_residual_m = s.residual_m.dot(s.normal);
      s.curvature_1_m = curvature[v];
      s.clamp_distance_m = std::numeric_limits<double>::infinity();
      for (const ClampSpec& clamp : clamps) s.clamp_distance_m = std::min(s.clamp_distance_m, grip_patch_distance_m(clamp, s.uv_m));
      error_sum += s.error_m();
      field.samples.push_back(s);
      ++fs.samples;
    }
    fs.mean_error_m = fs.samples > 0 ? error_sum / fs.samples : 0.0;
    field.stages.push_back(fs);
  }
}

}  // namespace twin::diagnosis
