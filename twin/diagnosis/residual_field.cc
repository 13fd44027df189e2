#include "twin/diagnosis/residual_field.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

#include "twin/dihedral_angle.h"
#include "twin/hinge_bending.h"
#include "twin/material_point.h"

namespace twin::diagnosis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool clamps_moved(const Trial& trial, int stage) {
  if (stage == 0) return true;  // placed
  const auto& a = trial.stages[stage - 1].poses;
  const auto& b = trial.stages[stage].poses;
  for (std::size_t c = 0; c < a.size() && c < b.size(); ++c) {
    if (a[c].engaged != b[c].engaged) return true;
    if (b[c].engaged && (a[c].position_m - b[c].position_m).norm() > 1e-9) return true;
  }
  return false;
}

std::string default_name(const Trial& trial) {
  std::filesystem::path p(trial.directory);
  if (p.filename().empty()) p = p.parent_path();
  const std::string name = p.filename().string();
  return name.empty() ? "trial" : name;
}

// Material distance from uv to the nearest engaged clamp's grip patch (m).
double clamp_distance(const Trial& trial, int stage, const Vec2& uv) {
  double best = std::numeric_limits<double>::infinity();
  const auto& poses = trial.stages[stage].poses;
  for (std::size_t c = 0; c < trial.clamps.size() && c < poses.size(); ++c) {
    if (!poses[c].engaged) continue;
    const double d = (uv - trial.clamps[c].material_point_m).norm() - trial.clamps[c].grip_radius_m;
    best = std::min(best, std::max(0.0, d));
  }
  return best;
}

}  // namespace

std::vector<int> ResidualField::samples_of_stage(int s) const {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(samples.size()); ++i)
    if (samples[i].stage == s) out.push_back(i);
  return out;
}

double stage_age_s(const Trial& trial, int stage) {
  int k = stage;
  while (k > 0 && !clamps_moved(trial, k)) --k;
  // At k == 0 the clamps were placed before the first scan at an unknown time.
  if (k == 0) return kNaN;
  const auto& now = trial.stages[stage].time_s;
  const auto& before = trial.stages[k - 1].time_s;
  if (!now || !before) return kNaN;
  return *now - *before;
}

double stage_load_m(const Trial& trial, int stage) {
  double base = 0.0;
  int count = 0;
  for (const ClampPose& p : trial.stages.at(0).poses)
    if (p.engaged) base += p.position_m.z(), ++count;
  if (count == 0) return 0.0;
  base /= count;
  double top = -std::numeric_limits<double>::infinity();
  for (const ClampPose& p : trial.stages.at(stage).poses)
    if (p.engaged) top = std::max(top, p.position_m.z());
  return std::isfinite(top) ? top - base : 0.0;
}

std::vector<Vec3> vertex_normals(const SheetMesh& mesh, const VecX& x) {
  std::vector<Vec3> n(mesh.vertex_count(), Vec3::Zero());
  for (const auto& t : mesh.triangles) {
    // The cross product is twice the area times the unit normal: area weighting for free.
    const Vec3 a = x.segment<3>(3 * t[0]), b = x.segment<3>(3 * t[1]), c = x.segment<3>(3 * t[2]);
    const Vec3 w = (b - a).cross(c - a);
    for (int v : t) n[v] += w;
  }
  for (Vec3& v : n) {
    const double len = v.norm();
    v = len > 0.0 ? Vec3(v / len) : Vec3::UnitZ();
  }
  return n;
}

std::vector<double> vertex_curvatures_1_m(const SheetMesh& mesh, const VecX& x) {
  // Across hinge e the sheet turns by theta over the distance between the two triangles'
  // centroids measured across the edge, d = 2 (A_a + A_b) / (3 |e|): normal curvature theta / d
  // in the direction t perpendicular to the edge (rest material frame). Per vertex, the tensor
  // K (uu, vv, uv) with t^T K t closest to its incident hinges' curvatures (least squares).
  const std::vector<Hinge> hinges = build_hinges(mesh);
  const int n = mesh.vertex_count();
  std::vector<std::vector<std::pair<Vec2, double>>> rows(n);
  for (const Hinge& h : hinges) {
    Vec12 xh;
    for (int k = 0; k < 4; ++k) xh.segment<3>(3 * k) = x.segment<3>(3 * h.v[k]);
    const double theta = dihedral_angle(xh, nullptr, nullptr);
    if (!std::isfinite(theta)) continue;
    const Vec2 e = mesh.rest_uv[h.v[1]] - mesh.rest_uv[h.v[0]];
    const double len = e.norm();
    const double d = 2.0 * (mesh.rest_area(h.triangle_a) + mesh.rest_area(h.triangle_b)) / (3.0 * len);
    const Vec2 t(-e.y() / len, e.x() / len);
    for (int k = 0; k < 2; ++k) rows[h.v[k]].emplace_back(t, theta / d);
  }
  std::vector<double> out(n, 0.0);
  for (int v = 0; v < n; ++v) {
    const auto& r = rows[v];
    if (r.empty()) continue;
    Eigen::MatrixXd A(r.size(), 3);
    Eigen::VectorXd b(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Vec2& t = r[i].first;
      A.row(i) << t.x() * t.x(), t.y() * t.y(), 2.0 * t.x() * t.y();
      b(i) = r[i].second;
    }
    // Minimum-norm solution: a boundary vertex with one or two hinges gets the tensor of least
    // size that explains them.
    const Eigen::Vector3d k = A.completeOrthogonalDecomposition().solve(b);
    out[v] = std::sqrt(k(0) * k(0) + k(1) * k(1) + 2.0 * k(2) * k(2));
  }
  return out;
}

void add_trial_residuals(ResidualField& field, const TrialEvaluator& evaluator, const TrialFit& fit,
                         const std::string& name) {
  const Trial& trial = evaluator.trial();
  const std::string label = name.empty() ? default_name(trial) : name;
  if (!fit.usable()) throw std::invalid_argument("residual field: trial " + label + ": fit not usable: " + fit.failure);
  if (fit.stages.size() != trial.stages.size())
    throw std::invalid_argument("residual field: trial " + label + ": fit has " + std::to_string(fit.stages.size()) +
                                " stages, the trial " + std::to_string(trial.stages.size()));
  const SheetMesh& mesh = evaluator.model().mesh();
  FieldTrial ft;
  ft.name = label;
  ft.sheet_min_uv_m = ft.sheet_max_uv_m = mesh.rest_uv.at(0);
  for (const Vec2& p : mesh.rest_uv) {
    ft.sheet_min_uv_m = ft.sheet_min_uv_m.cwiseMin(p);
    ft.sheet_max_uv_m = ft.sheet_max_uv_m.cwiseMax(p);
  }
  ft.grid_rows = trial.marker_grid_rows;
  ft.grid_cols = trial.marker_grid_cols;
  ft.marker_count = static_cast<int>(trial.marker_uv_m.size());
  const int trial_index = static_cast<int>(field.trials.size());
  field.trials.push_back(ft);

  std::optional<MaterialPointMap> points;
  for (std::size_t s = 0; s < trial.stages.size(); ++s) {
    const TrialStage& stage = trial.stages[s];
    const StageFit& sf = fit.stages[s];
    if (!stage.observed.has_markers()) continue;
    if (!points) points.emplace(mesh, trial.marker_uv_m);
    const std::vector<Vec3> normals = vertex_normals(mesh, sf.x);
    const std::vector<double> curvature = vertex_curvatures_1_m(mesh, sf.x);
    const std::vector<Vec3> predicted =
        sf.predicted_markers_m.size() == trial.marker_uv_m.size() ? sf.predicted_markers_m : points->positions(sf.x);
    FieldStage fs;
    fs.trial = trial_index;
    fs.trial_stage = static_cast<int>(s);
    fs.id = stage.id;
    fs.label = label + "/" + stage.id;
    fs.age_s = stage_age_s(trial, static_cast<int>(s));
    fs.load_m = stage_load_m(trial, static_cast<int>(s));
    const int stage_index = static_cast<int>(field.stages.size());
    double error_sum = 0.0;
    for (std::size_t m = 0; m < stage.observed.markers_m.size(); ++m) {
      const Vec3& o = stage.observed.markers_m[m];
      if (!o.allFinite()) continue;
      const MaterialPointLocation& loc = points->location(static_cast<int>(m));
      ResidualSample sample;
      sample.trial = trial_index;
      sample.stage = stage_index;
      sample.marker = static_cast<int>(m);
      sample.uv_m = trial.marker_uv_m[m];
      sample.residual_m = o - predicted[m];
      Vec3 normal = Vec3::Zero();
      double kappa = 0.0;
      for (int k = 0; k < 3; ++k) {
        normal += loc.weights(k) * normals[loc.vertices[k]];
        kappa += loc.weights(k) * curvature[loc.vertices[k]];
      }
      sample.normal = normal.norm() > 0.0 ? Vec3(normal.normalized()) : Vec3::UnitZ();
      sample.normal_residual_m = sample.residual_m.dot(sample.normal);
      sample.clamp_distance_m = clamp_distance(trial, static_cast<int>(s), sample.uv_m);
      sample.curvature_1_m = kappa;
      error_sum += sample.error_m();
      field.samples.push_back(sample);
      ++fs.samples;
    }
    fs.mean_error_m = fs.samples > 0 ? error_sum / fs.samples : 0.0;
    field.stages.push_back(fs);
  }
}

}  // namespace twin::diagnosis
