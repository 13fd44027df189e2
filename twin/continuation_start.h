#pragma once
// Which earlier evaluation a new material's equilibria are continued from (trial_evaluator.h):
// a choice among the materials evaluated before, by their distance in search coordinates and
// by how well their equilibria fit the scans.

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace twin {

struct EvaluatedMaterial {
  Eigen::VectorXd coordinates;  // search coordinates (material_parameters.h)
  double sum_squares_m2 = 0.0;  // misfit of its equilibria to the scans
};

// The index of the material to continue from, or none when every one is farther than `reach`
// (max-norm distance; then the trial is simulated afresh) or has another parameter list.
// Within `one_step` of the target, the best-fitting material is chosen, not the nearest: an
// optimiser that rejects a trial point (its continuation crossed onto a worse branch) tries a
// shorter step next, which lies nearer the rejected point than the accepted one. Continuing
// from the rejected point carried its branch back in, every shorter step was rejected too,
// and Levenberg-Marquardt stopped on tiny gains between the rejections (clamp-grip refits of
// blind set 7001: accepted 8.2 mm, then two rejected at 10.1-10.2 mm, over and over; held-out
// 12.1 mm, 2.1 mm with this rule). Farther out, the nearest is chosen, and of equally near
// ones (the same material continued and simulated afresh) the better fit.
std::optional<std::size_t> continuation_start(const std::vector<EvaluatedMaterial>& evaluated,
                                              const Eigen::VectorXd& target, double one_step, double reach);

}  // namespace twin
