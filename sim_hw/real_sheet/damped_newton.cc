#include "sim_hw/real_sheet/damped_newton.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

namespace sim_hw::real_sheet {

double NewtonProblem::largest_force_N(const VecX& g) const {
  double m = 0;
  for (int i = 0; i < g.size() / 3; ++i) m = std::max(m, g.segment<3>(3 * i).norm());
  return m;
}

DampedNewtonReport damped_newton(NewtonProblem& problem, BlockSparseMatrix& H, Cholesky& cholesky, const VecX& metric,
                                 const DampedNewtonOptions& options) {
  DampedNewtonReport report;
  VecX g;
  double energy = problem.energy_at(nullptr, 0.0, &g);
  if (!std::isfinite(energy)) {
    report.message = "the starting shape has no finite energy";
    return report;
  }
  const double start_energy = energy;
  double mu = options.initial_damping_1_s2;
  const double mu_floor = 1.0;  // 1/s^2: below this a step is Newton's
  double mu_worked = 0.0;       // the last damping of an accepted step
  int failed_in_a_row = 0;
  problem.save();
  const auto fail = [&](std::string why) {
    problem.restore();
    report.message = std::move(why);
    return report;
  };
  int exact_pause = 0;                         // iterations left before the exact Hessian is tried again
  BlockSparseMatrix exact;                     // the unshifted exact Hessian, for shifted_exact
  double step_limit_m = options.step_limit_m;  // trust radius: no point moves further in a step
  for (report.iterations = 0; report.iterations < options.max_iterations; ++report.iterations) {
    report.max_force_N = problem.largest_force_N(g);
    report.energy_J = energy;
    if (report.max_force_N <= options.tolerance_N) {
      report.converged = true;
      return report;
    }
    // Factorise H + mu M with the exact Hessian. When that is not positive definite (compressed
    // membrane, a fold past its stable shape) the projected Hessian takes its place for a few
    // iterations, at the damping that last worked: positive semi-definite, so with mu > 0 it
    // factorises, and mu is left to the steps' success.
    bool factored = false;
    if (!options.projected_hessian && exact_pause == 0) {
      problem.hessian(H, Hessian::kExact);
      if (options.shifted_exact) exact = H;
      if (mu > 0) H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      factored = cholesky.factorize(H);
      double shift = std::max(mu_floor, 4.0 * mu);
      for (int attempt = 0; options.shifted_exact && !factored && attempt < 6; ++attempt, shift *= 8.0) {
        H = exact;
        H.add_to_diagonal(shift * metric);
        ++report.factorizations;
        factored = cholesky.factorize(H);
        if (factored) mu = shift;
      }
      if (!factored) exact_pause = 3;
    } else if (exact_pause > 0) {
      --exact_pause;
    }
    if (!factored) {
      if (mu == 0.0 && !options.projected_hessian) mu = std::max(mu_floor, 0.25 * mu_worked);
      problem.hessian(H, Hessian::kProjected);
      if (mu > 0) H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      factored = cholesky.factorize(H);
    }
    for (int attempt = 0; attempt < 40 && !factored; ++attempt) {  // a singular projection
      mu = std::max(8.0 * mu, 16.0 * mu_floor);
      problem.hessian(H, Hessian::kProjected);
      H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      factored = cholesky.factorize(H);
    }
    if (!factored) return fail("no damping made the Hessian positive definite");
    const VecX dx = cholesky.solve(-g);
    const double longest_m = problem.longest_move_m(dx);
    if (options.trace) {
      std::fprintf(stderr, "it %d E %.9g |g| %.3g mu %.3g |dx| %.3g limit %.3g\n", report.iterations, energy,
                   report.max_force_N, mu, longest_m, step_limit_m);
    }
    if (mu == 0.0 && longest_m < options.step_tolerance_m) {
      problem.move(dx, 1.0);
      report.energy_J = problem.energy_at(nullptr, 0.0, &g);
      report.max_force_N = problem.largest_force_N(g);
      ++report.iterations;
      report.converged = true;
      return report;
    }
    // Backtracking from the step cut to the trust radius: accept the first alpha whose energy
    // falls (or, within rounding of the energy, whose force falls).
    const double cut = std::min(1.0, step_limit_m / std::max(longest_m, 1e-300));
    double alpha = cut;
    bool accepted = false;
    VecX g_try;
    const double slope = g.dot(dx);
    for (int k = 0; k < 8; ++k, alpha *= 0.5) {
      const double e = problem.energy_at(&dx, alpha, &g_try);
      if (!std::isfinite(e)) continue;
      const double rounding = 1e-12 * std::max(1.0, std::abs(energy));
      if (e <= energy + 1e-4 * alpha * slope ||
          (std::abs(e - energy) <= rounding && problem.largest_force_N(g_try) < report.max_force_N)) {
        accepted = true;
        energy = e;
        break;
      }
    }
    if (!accepted) {
      if (++failed_in_a_row > 12) return fail(fmt::format("no step lowered the energy (force {:.3g} N)", report.max_force_N));
      mu = std::max(mu * 8.0, mu_floor * 64.0);
      step_limit_m = std::max(1e-6, 0.25 * alpha * longest_m);
      continue;
    }
    failed_in_a_row = 0;
    if (mu > 0) mu_worked = mu;
    problem.move(dx, alpha);
    g = std::move(g_try);
    if (alpha == 1.0) {  // the whole step: trust it more
      mu = mu / 4.0;
      if (mu < mu_floor) mu = 0.0;
      step_limit_m = std::max(step_limit_m, std::min(0.2, 2.0 * longest_m));
    } else if (alpha == cut) {  // cut by the trust radius only: widen it
      step_limit_m = std::max(step_limit_m, std::min(0.2, 2.0 * step_limit_m));
    } else {  // backtracked: the model was poor this far out
      mu = std::max(mu * 4.0, mu_floor * 16.0);
      step_limit_m = std::max(1e-6, alpha * longest_m);
    }
  }
  report.max_force_N = problem.largest_force_N(g);
  report.energy_J = energy;
  report.converged = report.max_force_N <= options.tolerance_N;
  if (!report.converged && options.keep_on_limit && report.energy_J <= start_energy && std::isfinite(report.energy_J)) {
    report.budget_used = true;
    report.message = "iteration budget used";
    return report;
  }
  if (!report.converged) {
    return fail(fmt::format("iteration limit ({}) at force {:.3g} N", options.max_iterations, report.max_force_N));
  }
  return report;
}

}  // namespace sim_hw::real_sheet
