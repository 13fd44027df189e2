#include "twin/diagnosis/residual_field.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

#include "twin/mesh/material_point.h"
#include "twin/trials/stage_age.h"

namespace twin::diagnosis {
namespace {

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
    best = std::min(best, grip_patch_distance_m(trial.clamps[c], uv));
  }
  return best;
}

}  // namespace

FieldTrial field_trial_on(const SheetMesh& mesh, const std::string& name) {
  FieldTrial ft;
  ft.name = name;
  ft.sheet_min_uv_m = ft.sheet_max_uv_m = mesh.rest_uv.at(0);
  for (const Vec2& p : mesh.rest_uv) {
    ft.sheet_min_uv_m = ft.sheet_min_uv_m.cwiseMin(p);
    ft.sheet_max_uv_m = ft.sheet_max_uv_m.cwiseMax(p);
  }
  return ft;
}

double grip_patch_distance_m(const ClampSpec& clamp, const Vec2& uv) {
  return std::max(0.0, (uv - clamp.material_point_m).norm() - clamp.grip_radius_m);
}

std::vector<int> ResidualField::samples_of_stage(int s) const {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(samples.size()); ++i)
    if (samples[i].stage == s) out.push_back(i);
  return out;
}

double stage_age_s(const Trial& trial, int stage) {
  // One definition of the age, the one the twin's relaxation uses (twin/trials/stage_age.h).
  return stage_load_ages_s(trial.stages).at(stage);
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
  // Shape operator from the vertex normals: in each triangle the normal's gradient over the
  // material coordinates, G = dn/d(u, v) (3 x 2), and the deformation gradient F = dx/d(u, v);
  // the curvature tensor is K = -sym(F^T G) (1/m, material frame, exact for an isometric
  // bending). Per vertex, the area-weighted mean of its triangles' K. Dihedral angles across
  // single hinges are not used: on a mesh inscribed in a curved surface the triangles' normals
  // tilt alternately (a discretisation pattern, not curvature), which the smoothed vertex
  // normals average out.
  const std::vector<Vec3> normals = vertex_normals(mesh, x);
  const int n = mesh.vertex_count();
  std::vector<Mat2> sum(n, Mat2::Zero());
  std::vector<double> weight(n, 0.0);
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    Mat2 duv;
    duv.col(0) = mesh.rest_uv[tri[1]] - mesh.rest_uv[tri[0]];
    duv.col(1) = mesh.rest_uv[tri[2]] - mesh.rest_uv[tri[0]];
    const double det = duv.determinant();
    if (std::abs(det) <= 1e-300) continue;
    const Mat2 inv = duv.inverse();
    Eigen::Matrix<double, 3, 2> dx, dn;
    dx.col(0) = x.segment<3>(3 * tri[1]) - x.segment<3>(3 * tri[0]);
    dx.col(1) = x.segment<3>(3 * tri[2]) - x.segment<3>(3 * tri[0]);
    dn.col(0) = normals[tri[1]] - normals[tri[0]];
    dn.col(1) = normals[tri[2]] - normals[tri[0]];
    const Eigen::Matrix<double, 3, 2> F = dx * inv, G = dn * inv;
    const Mat2 FG = F.transpose() * G;
    const Mat2 K = -0.5 * (FG + FG.transpose());
    const double area = 0.5 * std::abs(det);
    for (int v : tri) sum[v] += area * K, weight[v] += area;
  }
  std::vector<double> out(n, 0.0);
  for (int v = 0; v < n; ++v)
    if (weight[v] > 0.0) out[v] = (sum[v] / weight[v]).norm();  // Frobenius: sqrt(k1^2 + k2^2)
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
  FieldTrial ft = field_trial_on(mesh, label);
  ft.grid_rows = trial.marker_grid_rows;
  ft.grid_cols = trial.marker_grid_cols;
  ft.marker_count = static_cast<int>(trial.marker_uv_m.size());
  const int trial_index = static_cast<int>(field.trials.size());
  field.trials.push_back(ft);

  std::optional<MaterialPointMap> points;
  for (std::size_t s = 0; s < trial.stages.size(); ++s) {
    const TrialStage& stage = trial.stages[s];
    const StageFit& sf = fit.stages[s];
    if (s == 0 || !scans_same_pose(trial.stages[s - 1], stage)) ++field.pose_groups;
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
    fs.pose_group = field.pose_groups - 1;
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
      sample.observed_m = o;
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
