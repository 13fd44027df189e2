#pragma once
// Levenberg-Marquardt for small nonlinear least-squares problems whose residuals come from
// simulations that can fail: minimise S(y) = |r(y)|^2 within box bounds, with the Jacobian
// J = dr/dy given by the caller (for identification: the equilibria's tangents).
//
// Why not L-BFGS on S: identification's objective is a sum of squares whose Jacobian is cheap
// once the equilibria are factorised, and the Gauss-Newton matrix J^T J already carries the
// curvature L-BFGS has to learn from many gradients. Where the data barely determine a
// combination of parameters (tensile against shear on a hanging sheet), L-BFGS walked a flat
// valley for 48 evaluations; J^T J sees the valley from the first step.
// Why not Eigen's unsupported LevenbergMarquardt (MINPACK's lmder): it ends the search when an
// evaluation fails, and a trial material whose sheet finds no equilibrium is an ordinary event
// here (the step is then shortened, as for a step that does not reduce S), and it has no bounds.

#include <functional>
#include <string>

#include <Eigen/Core>

namespace twin {

struct LeastSquaresPoint {
  bool usable = false;        // false: the residuals could not be computed (simulation failed)
  Eigen::VectorXd residuals;  // r(y), any units; a fixed length over the search
  Eigen::MatrixXd jacobian;   // dr/dy, residuals x parameters
};

struct LevenbergMarquardtOptions {
  int max_evaluations = 40;
  // Stop when an accepted step changed no coordinate by more than this.
  double x_tolerance = 5e-3;
  // Stop when an accepted step lowered S by less than this fraction of S.
  double f_tolerance = 1e-4;
  // Damping relative to diag(J^T J) at the first step (Marquardt's scaling).
  double initial_damping = 1e-3;
};

struct LevenbergMarquardtResult {
  Eigen::VectorXd coordinates;  // the lowest S found
  double sum_squares = 0.0;     // S there
  int evaluations = 0;
  bool converged = false;
  std::string stop_reason;
};

// Starts at y0 (clamped to [lower, upper]); every trial step is clamped to the box. Throws
// std::invalid_argument when the sizes disagree or the start is not usable.
LevenbergMarquardtResult levenberg_marquardt(
    const std::function<LeastSquaresPoint(const Eigen::VectorXd& y)>& residuals, Eigen::VectorXd y0,
    const Eigen::VectorXd& lower, const Eigen::VectorXd& upper, const LevenbergMarquardtOptions& options);

}  // namespace twin
