#include "sim_hw/real_sheet/equilibrium_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>


namespace sim_hw::real_sheet {
namespace {

double max_block_norm(const VecX& g) {
  double m = 0;
  for (int i = 0; i < g.size() / 3; ++i) m = std::max(m, g.segment<3>(3 * i).norm());
  return m;
}

// The jaws after a step of alpha along dx's rotation part.
std::vector<JawHold> turned(const std::vector<JawHold>& jaws, const VecX& dx, int nodes, double alpha) {
  std::vector<JawHold> out = jaws;
  int pivot = nodes;
  for (JawHold& j : out) {
    if (j.pad.kind != JawKind::kPivot) continue;
    j.rotation = rotation_exp(alpha * dx.segment<3>(3 * pivot)) * j.rotation;
    ++pivot;
  }
  return out;
}

}  // namespace

SolveWorkspace::SolveWorkspace() : cholesky_(std::make_unique<Cholesky>()) {}
SolveWorkspace::~SolveWorkspace() = default;

BlockSparseMatrix& SolveWorkspace::pattern(const SheetModel& model, const std::vector<JawHold>& jaws) {
  std::vector<std::vector<int>> key;
  for (const JawHold& j : jaws) {
    key.push_back(pad_nodes(j.pad));
    key.back().push_back(j.pad.kind == JawKind::kPivot ? -1 : -2);
  }
  if (!built_ || key != key_) {
    pattern_ = model.hessian_pattern(jaws);
    key_ = std::move(key);
    built_ = true;
  }
  return pattern_;
}

EquilibriumReport solve_equilibrium(const SheetModel& model, VecX& x, std::vector<JawHold>& jaws,
                                    const EquilibriumOptions& options, const StepTerms* step,
                                    SolveWorkspace* workspace) {
  EquilibriumReport report;
  const int n = model.node_count();
  const double tolerance_N = options.force_tolerance * model.total_weight_N();
  // Damping metric: node masses; a pivot's turn weighs the pad's area moment of the sheet's
  // density (kg m^2), so mu M is a pseudo-time on both.
  const int dofs = model.dof_count(jaws);
  VecX metric(dofs);
  for (int i = 0; i < n; ++i) metric.segment<3>(3 * i).setConstant(model.node_mass_kg()[i]);
  {
    int pivot = n;
    for (const JawHold& j : jaws) {
      if (j.pad.kind != JawKind::kPivot) continue;
      double moment_m4 = 0;
      for (const JawSample& s : j.pad.samples) moment_m4 += s.area_m2 * s.offset_m.squaredNorm();
      metric.segment<3>(3 * pivot).setConstant(std::max(1e-12, model.material().density_kg_m2 * moment_m4));
      ++pivot;
    }
  }
  SolveWorkspace local;
  SolveWorkspace& work = workspace ? *workspace : local;
  BlockSparseMatrix& H = work.pattern(model, jaws);
  Cholesky& cholesky = work.cholesky();
  VecX g;
  double energy = model.energy(x, jaws, &g, nullptr, Hessian::kExact, step);
  if (!std::isfinite(energy)) {
    report.message = "the starting shape has no finite energy";
    return report;
  }
  const double start_energy = energy;
  double mu = options.initial_damping_1_s2;
  const double mu_floor = 1.0;  // 1/s^2: below this a step is Newton's
  double mu_worked = 0.0;       // the last damping of an accepted step
  int failed_in_a_row = 0;
  const VecX x_start = x;
  const std::vector<JawHold> jaws_start = jaws;
  const auto fail = [&](std::string why) {
    x = x_start;
    jaws = jaws_start;
    report.message = std::move(why);
    return report;
  };
  int exact_pause = 0;       // iterations left before the exact Hessian is tried again
  double step_limit_m = options.step_limit_m;  // trust radius: no node moves further in a step
  const bool trace = std::getenv("REAL_SHEET_TRACE") != nullptr;
  for (report.iterations = 0; report.iterations < options.max_iterations; ++report.iterations) {
    report.max_force_N = max_block_norm(g);
    report.energy_J = energy;
    if (report.max_force_N <= tolerance_N) {
      report.converged = true;
      return report;
    }
    // Factorise H + mu M with the exact Hessian. When that is not positive definite (compressed
    // membrane, a fold past its stable shape) the projected Hessian takes its place for a few
    // iterations, at the damping that last worked: positive semi-definite, so with mu > 0 it
    // factorises, and mu is left to the steps' success.
    bool factored = false;
    if (!options.projected_hessian && exact_pause == 0) {
      model.energy(x, jaws, nullptr, &H, Hessian::kExact, step);
      if (mu > 0) H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      factored = cholesky.factorize(H);
      if (!factored) exact_pause = 3;
    } else if (exact_pause > 0) {
      --exact_pause;
    }
    if (!factored) {
      if (mu == 0.0 && !options.projected_hessian) mu = std::max(mu_floor, 0.25 * mu_worked);
      model.energy(x, jaws, nullptr, &H, Hessian::kProjected, step);
      if (mu > 0) H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      factored = cholesky.factorize(H);
    }
    for (int attempt = 0; attempt < 40 && !factored; ++attempt) {  // a singular projection
      mu = std::max(8.0 * mu, 16.0 * mu_floor);
      model.energy(x, jaws, nullptr, &H, Hessian::kProjected, step);
      H.add_to_diagonal(mu * metric);
      ++report.factorizations;
      factored = cholesky.factorize(H);
    }
    if (!factored) return fail("no damping made the Hessian positive definite");
    const VecX dx = cholesky.solve(-g);
    const double longest_m = dx.head(3 * n).lpNorm<Eigen::Infinity>();
    if (trace) {
      std::fprintf(stderr, "it %d E %.9g |g| %.3g mu %.3g |dx| %.3g limit %.3g\n", report.iterations, energy,
                   report.max_force_N, mu, longest_m, step_limit_m);
    }
    if (mu == 0.0 && longest_m < options.step_tolerance_m) {
      x += dx.head(3 * n);
      jaws = turned(jaws, dx, n, 1.0);
      report.energy_J = model.energy(x, jaws, &g, nullptr, Hessian::kExact, step);
      report.max_force_N = max_block_norm(g);
      ++report.iterations;
      report.converged = true;
      return report;
    }
    // Backtracking from the step cut to the trust radius: accept the first alpha whose energy
    // falls (or, within rounding of the energy, whose force falls).
    const double cut = std::min(1.0, step_limit_m / std::max(longest_m, 1e-300));
    double alpha = cut;
    bool accepted = false;
    VecX x_try, g_try;
    std::vector<JawHold> jaws_try;
    const double slope = g.dot(dx);
    for (int k = 0; k < 8; ++k, alpha *= 0.5) {
      x_try = x + alpha * dx.head(3 * n);
      jaws_try = turned(jaws, dx, n, alpha);
      const double e = model.energy(x_try, jaws_try, &g_try, nullptr, Hessian::kExact, step);
      if (!std::isfinite(e)) continue;
      const double rounding = 1e-12 * std::max(1.0, std::abs(energy));
      if (e <= energy + 1e-4 * alpha * slope ||
          (std::abs(e - energy) <= rounding && max_block_norm(g_try) < report.max_force_N)) {
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
    x = std::move(x_try);
    jaws = std::move(jaws_try);
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
  report.max_force_N = max_block_norm(g);
  report.energy_J = energy;
  report.converged = report.max_force_N <= tolerance_N;
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
