#pragma once
// Residual fields made up directly (no simulation) for the diagnosis tests: a 17 x 17 marker grid
// on a 1.17 m x 0.975 m sheet, some stages, residual = Gaussian noise + a chosen smooth field.

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "twin/diagnosis/residual_field.h"

namespace diagnosis_test {

using twin::Vec2;
using twin::Vec3;
using twin::diagnosis::ResidualField;

// The model error added to marker (u, v) at stage s (m, world); the normal is +z.
using Shape = std::function<Vec3(const Vec2& uv, int stage)>;

inline Vec3 no_error(const Vec2&, int) { return Vec3::Zero(); }

struct SyntheticOptions {
  int stages = 4;
  int rows = 17, cols = 17;
  double width_m = 1.17, height_m = 0.975;
  double sigma_m = 0.3e-3;
  bool grid = true;            // false: the markers as a list, jittered off the grid
  unsigned seed = 1;
};

inline ResidualField synthetic_field(const SyntheticOptions& o, const Shape& shape) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> noise(0.0, o.sigma_m);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  ResidualField field;
  twin::diagnosis::FieldTrial trial;
  trial.name = "synthetic";
  trial.sheet_max_uv_m = Vec2(o.width_m, o.height_m);
  if (o.grid) trial.grid_rows = o.rows, trial.grid_cols = o.cols;
  trial.marker_count = o.rows * o.cols;
  field.trials.push_back(trial);
  const Vec2 spacing(o.width_m / o.cols, o.height_m / o.rows);
  // Off the grid, each marker sits where it was glued, the same in every stage.
  std::vector<Vec2> offset(static_cast<std::size_t>(o.rows * o.cols), Vec2::Zero());
  if (!o.grid)
    for (Vec2& d : offset) d = Vec2(jitter(rng) * spacing.x(), jitter(rng) * spacing.y());
  for (int s = 0; s < o.stages; ++s) {
    twin::diagnosis::FieldStage stage;
    stage.trial_stage = s;
    stage.id = std::to_string(s + 1);
    stage.label = "synthetic/" + stage.id;
    stage.age_s = NAN;
    stage.load_m = 0.1 * s;
    double sum = 0.0;
    for (int r = 0; r < o.rows; ++r)
      for (int c = 0; c < o.cols; ++c) {
        twin::diagnosis::ResidualSample m;
        m.trial = 0;
        m.stage = s;
        m.marker = r * o.cols + c;
        m.uv_m = Vec2((c + 0.5) * spacing.x(), (r + 0.5) * spacing.y());
        m.uv_m += offset[static_cast<std::size_t>(m.marker)];
        m.residual_m = shape(m.uv_m, s) + Vec3(noise(rng), noise(rng), noise(rng));
        m.observed_m = Vec3(m.uv_m.x(), m.uv_m.y(), 1.0) + m.residual_m;  // predicted: the sheet flat at z = 1 m
        m.normal = Vec3::UnitZ();
        m.normal_residual_m = m.residual_m.z();
        m.clamp_distance_m = (m.uv_m - Vec2(0.0, o.height_m)).norm();  // one clamp at the top-left corner
        m.curvature_1_m = 1.0;
        sum += m.error_m();
        field.samples.push_back(m);
        ++stage.samples;
      }
    stage.mean_error_m = sum / stage.samples;
    field.stages.push_back(stage);
  }
  return field;
}

}  // namespace diagnosis_test
