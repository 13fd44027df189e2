// Identification by derivatives: least squares on the markers in search coordinates (log p for
// stiffnesses, p / scale for effect parameters: material_parameters.h), either by
// Levenberg-Marquardt on the residuals with the equilibria's tangents as Jacobian (the default)
// or by NLopt LD_LBFGS on their mean square with the gradient by adjoint solves
// (trial_evaluator.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlopt.hpp>

#include "twin/trials/identification.h"
#include "twin/solvers/levenberg_marquardt.h"

namespace twin {
namespace {

// The objective in mm^2 (mean squared residual per coordinate): values of order 1-100 keep
// L-BFGS's tolerances meaningful.
constexpr double kMm2PerM2 = 1e6;
// For a material whose simulation fails: far above any sheet that hangs, with no slope, so
// the line search backs off.
constexpr double kFailedObjective_mm2 = 1e8;

// The physical bounds of each parameter, in its search coordinate.
std::pair<double, double> sane_bounds(MaterialParameter p) {
  const ParameterScale s = parameter_scale(p);
  return {to_search_coordinate(p, s.lower), to_search_coordinate(p, s.upper)};
}

}  // namespace

const char* optimizer_name(GradientOptimizer optimizer) {
  return optimizer == GradientOptimizer::kLbfgs ? "lbfgs" : "lm";
}

GradientOptimizer optimizer_from_name(const std::string& name) {
  if (name == "lm") return GradientOptimizer::kLevenbergMarquardt;
  if (name == "lbfgs") return GradientOptimizer::kLbfgs;
  throw std::invalid_argument("optimizer: expected lm or lbfgs, got '" + name + "'");
}

IdentificationResult identify_gradient(IdentificationProblem& problem, const GradientOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int simulations_before = problem.simulations();
  IdentificationResult result;
  const bool lbfgs = options.optimizer == GradientOptimizer::kLbfgs;
  result.method = lbfgs ? "ours: adjoint gradient + LD_LBFGS" : "ours: equilibrium tangents + Levenberg-Marquardt";
  // Equilibria continued from another method's materials would carry its choice of branches.
  problem.forget_warm_starts();
  result.objective_name = "mean squared marker residual per coordinate (mm^2)";
  const VecX x0 = options.start_coordinates.value_or(problem.coordinates_of(problem.base()));
  const int P = static_cast<int>(x0.size());
  result.start_coordinates = x0;
  std::vector<double> x(x0.data(), x0.data() + P), lower(P), upper(P);
  for (int j = 0; j < P; ++j) {
    std::tie(lower[j], upper[j]) = sane_bounds(problem.parameters()[j]);
    x[j] = std::clamp(x[j], lower[j], upper[j]);
    const double reach = parameter_scale(problem.parameters()[j]).logarithmic
                             ? std::log(options.search_ratio)
                             : options.linear_search_span;
    lower[j] = std::max(lower[j], x[j] - reach);
    upper[j] = std::min(upper[j], x[j] + reach);
  }
  nlopt::opt opt(nlopt::LD_LBFGS, static_cast<unsigned>(P));
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_maxeval(options.max_evaluations);
  opt.set_xtol_abs(options.x_tolerance);
  opt.set_ftol_rel(options.f_tolerance);
  struct Context {
    IdentificationProblem* problem;
    IdentificationResult* result;
    double best = std::numeric_limits<double>::infinity();
    VecX best_x;
  } context{&problem, &result, std::numeric_limits<double>::infinity(), VecX()};
  opt.set_min_objective(
      [](unsigned n, const double* v, double* grad, void* data) {
        auto* c = static_cast<Context*>(data);
        const VecX at = Eigen::Map<const VecX>(v, n);
        const auto e = c->problem->evaluate(at, grad ? Derivatives::kGradient : Derivatives::kNone, 0.5);
        ++c->result->evaluations;
        if (!e.usable()) {
          if (grad) std::fill(grad, grad + n, 0.0);
          return kFailedObjective_mm2;
        }
        const double f = kMm2PerM2 * e.mean_square_m2;
        if (grad) {
          for (unsigned j = 0; j < n; ++j) grad[j] = kMm2PerM2 * e.coordinate_gradient(j);
        }
        if (f < c->best) {
          c->best = f;
          c->best_x = at;
        }
        return f;
      },
      &context);
  // Levenberg-Marquardt's residuals: the stacked marker residuals (m) and their tangents.
  const auto residuals = [&](const VecX& at) {
    const auto e = problem.evaluate(at, Derivatives::kJacobian, 0.5);
    ++result.evaluations;
    LeastSquaresPoint point;
    point.usable = e.usable();
    if (!point.usable) return point;
    point.residuals = e.residuals_m;
    point.jacobian = e.coordinate_jacobian;
    const double f = kMm2PerM2 * e.mean_square_m2;
    if (f < context.best) {
      context.best = f;
      context.best_x = at;
    }
    return point;
  };
  const VecX lower_y = Eigen::Map<const VecX>(lower.data(), P);
  const VecX upper_y = Eigen::Map<const VecX>(upper.data(), P);
  double value = std::numeric_limits<double>::infinity();
  for (int round = 0;; ++round) {
    const int budget = std::max(1, options.max_evaluations - result.evaluations);
    if (!lbfgs) {
      LevenbergMarquardtOptions lm;
      lm.max_evaluations = budget;
      lm.x_tolerance = options.x_tolerance;
      lm.f_tolerance = options.f_tolerance;
      try {
        const LevenbergMarquardtResult r =
            levenberg_marquardt(residuals, Eigen::Map<const VecX>(x.data(), P), lower_y, upper_y, lm);
        x.assign(r.coordinates.data(), r.coordinates.data() + P);
        value = context.best;
        result.stop_reason = r.stop_reason;
      } catch (const std::invalid_argument&) {
        result.stop_reason = "the start material does not simulate";
      }
    } else {
      try {
        opt.set_maxeval(budget);
        const nlopt::result r = opt.optimize(x, value);
        switch (r) {
          case nlopt::XTOL_REACHED: result.stop_reason = "parameters converged"; break;
          case nlopt::FTOL_REACHED: result.stop_reason = "objective converged"; break;
          case nlopt::MAXEVAL_REACHED: result.stop_reason = "evaluation budget reached"; break;
          default: result.stop_reason = fmt::format("NLopt result {}", static_cast<int>(r));
        }
      } catch (const std::exception& e) {
        // L-BFGS gives up on round-off near the optimum; the best point seen is still the answer.
        result.stop_reason = fmt::format("NLopt stopped: {}", e.what());
      }
    }
    if (round == options.max_restarts || context.best_x.size() != P ||
        result.evaluations >= options.max_evaluations) {
      break;
    }
    // Re-simulate from scratch at the best point: does a fresh choice of branches fit better?
    const double before = context.best;
    const VecX at = context.best_x;
    std::vector<double> g(P);
    const double fresh = [&] {
      const auto e = problem.evaluate(at, Derivatives::kNone, 0.5, /*fresh=*/true);
      ++result.evaluations;
      return e.usable() ? kMm2PerM2 * e.mean_square_m2 : kFailedObjective_mm2;
    }();
    if (fresh < context.best) {
      context.best = fresh;
      context.best_x = at;
    }
    if (!(fresh < (1.0 - options.restart_gain) * before)) break;
    result.stop_reason += fmt::format("; restarted after a fresh simulation fitted better ({:.4g} -> {:.4g} mm^2)",
                                      before, fresh);
    x.assign(at.data(), at.data() + P);
  }
  if (context.best_x.size() == P) {
    result.coordinates = context.best_x;
    result.objective = context.best;
  } else {
    result.coordinates = Eigen::Map<const VecX>(x.data(), P);
    result.objective = value;
    result.stop_reason += "; no simulation succeeded";
  }
  result.at_search_edge.assign(P, 0);
  for (int j = 0; j < P; ++j) {
    if (result.coordinates(j) <= lower[j] + 1e-6 || result.coordinates(j) >= upper[j] - 1e-6) {
      result.at_search_edge[j] = result.coordinates(j) <= lower[j] + 1e-6 ? -1 : 1;
      result.stop_reason += fmt::format("; {} at the edge of its search range: restart from there",
                                        parameter_name(problem.parameters()[j]));
    }
  }
  result.material = problem.material_at(result.coordinates);
  result.simulations = problem.simulations() - simulations_before;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace twin
