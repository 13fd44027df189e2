#include "sim_hw/spline_shell/preconditioned_lbfgs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <vector>

#include <fmt/format.h>

namespace sim_hw::spline_shell {

using real_sheet::Hessian;
using VecX = Eigen::VectorXd;

namespace {

// The inverse-Hessian model's curvature pairs: s (a step), y (the gradient's change along it).
struct Pair {
  VecX s, y;
  double rho;  // 1 / s.y
};

}  // namespace

LbfgsReport preconditioned_lbfgs(real_sheet::NewtonProblem& problem, real_sheet::BlockSparseMatrix& H,
                                 real_sheet::Cholesky& cholesky, const VecX& metric, const LbfgsOptions& options) {
  LbfgsReport report;
  VecX g;
  double energy = problem.energy_at(nullptr, 0.0, &g);
  ++report.evaluations;
  report.energy_J = energy;
  report.max_force_N = problem.largest_force_N(g);
  if (!std::isfinite(energy)) {
    report.message = "the starting shape has no finite energy";
    return report;
  }
  std::deque<Pair> pairs;
  int on_this_factor = 0;
  bool factored = false;
  // H (exact) at the current state, shifted by mu M until it factorises, then the projected one.
  const auto factorize = [&]() {
    ++report.factorizations;
    problem.hessian(H, Hessian::kExact);
    if (cholesky.factorize(H)) return true;
    for (double mu = 1.0; mu < 1e7; mu *= 16.0) {
      problem.hessian(H, mu < 1e3 ? Hessian::kExact : Hessian::kProjected);
      H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      if (cholesky.factorize(H)) return true;
    }
    return false;
  };
  for (report.iterations = 0; report.iterations < options.max_iterations; ++report.iterations) {
    report.max_force_N = problem.largest_force_N(g);
    report.energy_J = energy;
    if (report.max_force_N <= options.tolerance_N) {
      report.converged = true;
      return report;
    }
    if (!factored || on_this_factor >= options.refactor_every) {
      factored = factorize();
      on_this_factor = 0;
      if (!factored) {
        report.message = "no shift made the Hessian positive definite";
        return report;
      }
    }
    // Two-loop recursion: d = -B^-1 g, B^-1 the pairs' update of the factor's inverse.
    VecX q = g;
    std::vector<double> a(pairs.size());
    for (std::size_t i = pairs.size(); i-- > 0;) {
      a[i] = pairs[i].rho * pairs[i].s.dot(q);
      q -= a[i] * pairs[i].y;
    }
    VecX d = cholesky.solve(q);
    for (std::size_t i = 0; i < pairs.size(); ++i) d += (a[i] - pairs[i].rho * pairs[i].y.dot(d)) * pairs[i].s;
    d = -d;
    double slope = g.dot(d);
    if (!(slope < 0)) {  // the pairs made no descent: the factor alone does
      pairs.clear();
      d = -cholesky.solve(g);
      slope = g.dot(d);
    }
    const double longest_m = problem.longest_move_m(d);
    const double cut = std::min(1.0, options.step_limit_m / std::max(longest_m, 1e-300));
    double alpha = cut;
    bool accepted = false;
    VecX g_try;
    // Backtracking to the minimum of the parabola through the energy, its slope and the trial
    // (kept between a tenth and a half of the trial step): a quasi-Newton step on a fold
    // overshoots by a factor of a few, and halving alone takes several evaluations to find it.
    for (int k = 0; k < 12; ++k) {
      const double e = problem.energy_at(&d, alpha, &g_try);
      ++report.evaluations;
      const double rounding = 1e-12 * std::max(1.0, std::abs(energy));
      if (std::isfinite(e) && (e <= energy + 1e-4 * alpha * slope ||
                               (std::abs(e - energy) <= rounding && problem.largest_force_N(g_try) < report.max_force_N))) {
        accepted = true;
        energy = e;
        break;
      }
      const double curvature = std::isfinite(e) ? 2.0 * (e - energy - slope * alpha) / (alpha * alpha) : 0.0;
      const double vertex = curvature > 0 ? -slope / curvature : 0.0;
      alpha = std::clamp(vertex, 0.1 * alpha, 0.5 * alpha);
    }
    if (options.trace) {
      std::fprintf(stderr, "lbfgs %d E %.9g |g| %.3g |d| %.3g alpha %.3g pairs %zu%s\n", report.iterations, energy,
                   report.max_force_N, longest_m, accepted ? alpha : 0.0, pairs.size(), accepted ? "" : " (refactor)");
    }
    if (!accepted) {
      // First forget the pairs, then factorise here; a fresh factor alone that finds no descent
      // ends the relaxation.
      if (pairs.empty() && on_this_factor == 0) {
        report.message = fmt::format("no step lowered the energy (force {:.3g} N)", report.max_force_N);
        return report;
      }
      if (pairs.empty() || on_this_factor > 0) factored = false;
      pairs.clear();
      continue;
    }
    problem.move(d, alpha);
    Pair p{alpha * d, g_try - g, 0.0};
    const double sy = p.s.dot(p.y);
    if (sy > 1e-12 * p.s.norm() * p.y.norm()) {  // curvature along the step: keep the pair
      p.rho = 1.0 / sy;
      pairs.push_back(std::move(p));
      if (static_cast<int>(pairs.size()) > options.memory) pairs.pop_front();
    }
    g = std::move(g_try);
    ++on_this_factor;
  }
  report.max_force_N = problem.largest_force_N(g);
  report.energy_J = energy;
  report.converged = report.max_force_N <= options.tolerance_N;
  if (!report.converged) report.message = fmt::format("iteration limit ({})", options.max_iterations);
  return report;
}

}  // namespace sim_hw::spline_shell
