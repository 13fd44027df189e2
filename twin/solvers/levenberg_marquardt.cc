// Levenberg-Marquardt with Marquardt's diagonal scaling and Nielsen's damping update
// (H. B. Nielsen, "Damping parameter in Marquardt's method", IMM DTU 1999): a step that lowers S
// by a good share of what the linear model predicts loosens the damping smoothly, one that does
// not (or whose simulation fails) is rejected and the damping grows, doubling its growth factor.
#include "twin/solvers/levenberg_marquardt.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Eigen/Cholesky>
#include <fmt/format.h>

namespace twin {
namespace {

// Damping beyond this (relative to diag(J^T J)) leaves steps far below any tolerance.
constexpr double kLargestDamping = 1e16;

bool finite_point(const LeastSquaresPoint& p, Eigen::Index residuals, Eigen::Index parameters) {
  return p.usable && p.residuals.size() == residuals && p.jacobian.rows() == residuals &&
         p.jacobian.cols() == parameters && p.residuals.allFinite() && p.jacobian.allFinite();
}

}  // namespace

namespace {

// The damped Gauss-Newton step with the coordinates that sit on a bound and would be pushed
// past it held there, the others solved for with those fixed (one pass of an active set). Cut
// back to the bounds afterwards, a step that pushes into a bound would otherwise carry the
// coupled coordinates with it as if the bound had not stopped it.
Eigen::VectorXd bounded_step(const Eigen::MatrixXd& damped, const Eigen::VectorXd& g, const Eigen::VectorXd& y,
                             const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  Eigen::VectorXd step = damped.ldlt().solve(-g);
  std::vector<Eigen::Index> moving;
  for (Eigen::Index j = 0; j < y.size(); ++j) {
    const bool held = (y(j) <= lower(j) && step(j) < 0.0) || (y(j) >= upper(j) && step(j) > 0.0);
    if (!held) moving.push_back(j);
  }
  if (moving.size() == static_cast<std::size_t>(y.size())) return step;
  step.setZero();
  if (moving.empty()) return step;
  const Eigen::Index m = static_cast<Eigen::Index>(moving.size());
  Eigen::MatrixXd sub(m, m);
  Eigen::VectorXd rhs(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    rhs(a) = -g(moving[a]);
    for (Eigen::Index b = 0; b < m; ++b) sub(a, b) = damped(moving[a], moving[b]);
  }
  const Eigen::VectorXd reduced = sub.ldlt().solve(rhs);
  for (Eigen::Index a = 0; a < m; ++a) step(moving[a]) = reduced(a);
  return step;
}

}  // namespace

LevenbergMarquardtResult levenberg_marquardt(
    const std::function<LeastSquaresPoint(const Eigen::VectorXd& y)>& residuals, Eigen::VectorXd y0,
    const Eigen::VectorXd& lower, const Eigen::VectorXd& upper, const LevenbergMarquardtOptions& options) {
  const Eigen::Index P = y0.size();
  if (lower.size() != P || upper.size() != P) {
    throw std::invalid_argument("levenberg_marquardt: bounds and start differ in size");
  }
  Eigen::VectorXd y = y0.cwiseMax(lower).cwiseMin(upper);
  LevenbergMarquardtResult out;
  LeastSquaresPoint at = residuals(y);
  ++out.evaluations;
  const Eigen::Index M = at.residuals.size();
  if (!finite_point(at, M, P) || M == 0) {
    throw std::invalid_argument("levenberg_marquardt: the start gives no usable residuals");
  }
  double S = at.residuals.squaredNorm();
  Eigen::MatrixXd A = at.jacobian.transpose() * at.jacobian;
  Eigen::VectorXd g = at.jacobian.transpose() * at.residuals;
  // Marquardt's scaling, kept at the largest diagonal seen (Moré): a parameter whose column
  // vanishes at one point still gets a damped, finite step.
  Eigen::VectorXd scale = A.diagonal().cwiseMax(1e-12 * std::max(A.diagonal().maxCoeff(), 1e-300));
  double damping = options.initial_damping;
  double growth = 2.0;
  out.stop_reason = "evaluation budget reached";
  while (out.evaluations < options.max_evaluations) {
    Eigen::MatrixXd damped = A;
    damped.diagonal() += damping * scale;
    const Eigen::VectorXd free_step = bounded_step(damped, g, y, lower, upper);
    Eigen::VectorXd step = (y + free_step).cwiseMax(lower).cwiseMin(upper) - y;
    const bool clamped = (step - free_step).cwiseAbs().maxCoeff() > 0.0;
    if (!step.allFinite()) {
      out.stop_reason = "the damped normal equations have no finite solution";
      break;
    }
    if (step.cwiseAbs().maxCoeff() < options.x_tolerance) {
      out.converged = true;
      out.stop_reason = "parameters converged";
      break;
    }
    // Reduction of S the linear model |r + J step|^2 predicts.
    const double predicted = -(2.0 * step.dot(g) + step.dot(A * step));
    if (!(predicted > 0.0) && clamped) {
      // The step left the bounds and, cut back to them, no longer descends (a direction the data
      // barely see makes the Gauss-Newton step long; cut off at a bound its other parts go
      // uphill). More damping turns the step towards the gradient and shortens it, until it
      // fits inside and descends: a rejected step, not the end of the search.
      damping *= growth;
      growth *= 2.0;
      if (damping > kLargestDamping) {
        out.stop_reason = fmt::format("no step within the bounds lowers the objective (damping {:.3g})", damping);
        break;
      }
      continue;
    }
    if (!(predicted > 0.0)) {
      out.converged = true;
      out.stop_reason = "no descent direction left (gradient zero within round-off)";
      break;
    }
    const Eigen::VectorXd y_trial = y + step;
    LeastSquaresPoint trial = residuals(y_trial);
    ++out.evaluations;
    const double S_trial = finite_point(trial, M, P) ? trial.residuals.squaredNorm()
                                                    : std::numeric_limits<double>::infinity();
    const double gain = (S - S_trial) / predicted;
    if (gain > 0.0) {
      const double relative_drop = (S - S_trial) / S;
      y = y_trial;
      S = S_trial;
      at = std::move(trial);
      A = at.jacobian.transpose() * at.jacobian;
      g = at.jacobian.transpose() * at.residuals;
      scale = scale.cwiseMax(A.diagonal());
      damping *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * gain - 1.0, 3));
      growth = 2.0;
      if (relative_drop < options.f_tolerance) {
        out.converged = true;
        out.stop_reason = "objective converged";
        break;
      }
    } else {
      damping *= growth;
      growth *= 2.0;
      if (damping > kLargestDamping) {
        out.stop_reason = fmt::format("no step lowers the objective (damping {:.3g})", damping);
        break;
      }
    }
  }
  out.coordinates = y;
  out.sum_squares = S;
  return out;
}

}  // namespace twin
