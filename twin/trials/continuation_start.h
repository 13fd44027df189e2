#pragma once
// Which earlier evaluations a new material's equilibria are continued from (trial_evaluator.h):
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

struct ContinuationStarts {
  // The nearest material within `reach` (max-norm distance) with the same parameter list; of
  // equally near ones (the same material continued, and simulated afresh) the better fit. None:
  // simulate afresh.
  std::optional<std::size_t> nearest;
  // The best-fitting material within one material step, when that is not `nearest`. An
  // optimiser that rejects a trial point (its continuation crossed onto a worse branch) tries a
  // shorter step next, which lies nearer the rejected point than the accepted one: continued
  // from the rejected point alone, it carried the worse branch back in, every shorter step was
  // rejected too, and Levenberg-Marquardt stopped on tiny gains between the rejections
  // (clamp-grip refits of blind set 7001: accepted 8.2 mm, then two rejected at 10.1-10.2 mm,
  // over and over). Continued from this one alone, a refit's path can lose a branch the nearest
  // would have kept, so both are continued and the better fit is kept. (Neither rule makes a
  // path through the branches safe: blind set 4001's nonlinear-bending refit found the truth
  // with the nearest alone, and ends on another equilibrium with this one alone or with both.)
  std::optional<std::size_t> best_nearby;
};

ContinuationStarts continuation_starts(const std::vector<EvaluatedMaterial>& evaluated, const Eigen::VectorXd& target,
                                       double one_step, double reach);

}  // namespace twin
