#pragma once
// The sheet of issue 2's benchmark, shared by the benchmark programs: the paper's composite
// (1.17 x 0.975 m, 0.3 kg/m^2, tensile 5000 N/m, shear 5000 N/m, bending 0.001 N*m, strain-rate
// viscosity 5 N*s/m) held by four clamps at distinct distances from the corners, 10 % closer to
// its centre than flat so it sags and wrinkles; clamp A then circles (5 cm radius, 2 s period)
// so the sheet never settles.

#include <vector>

#include "twin/model/clamp.h"
#include "twin/model/shell_model.h"

namespace twin::bench {

constexpr double kWidth_m = 1.17, kHeight_m = 0.975;

struct BenchmarkSheet {
  // A mesh of about `target_triangles` triangles.
  explicit BenchmarkSheet(int target_triangles);
  // The clamp poses at time t_s (s) of the circling motion.
  std::vector<ClampPose> circling_poses(double t_s) const;

  ShellModel model;
  ClampSet clamps;
  std::vector<ClampPose> poses;  // where the clamps hold the sheet at rest
  VecX flat;                     // the flat sheet, 1 m above the floor
};

// The sheet's static equilibrium from flat, then `steps` linearised backward-Euler steps of dt_s
// while clamp A circles: x[k], v[k] at the start of step k (k = 0..steps), as the studies of the
// moving sheet's Hessian use them. Throws std::runtime_error when a solve fails.
struct CirclingStates {
  std::vector<VecX> x, v;
};
CirclingStates circling_states(const BenchmarkSheet& sheet, int steps, double dt_s);

}  // namespace twin::bench
