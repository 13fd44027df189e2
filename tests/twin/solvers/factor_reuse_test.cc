#include <catch2/catch.hpp>

#include <random>

#include "twin/solvers/newton_linear_solver.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace twin {
namespace {

// The lagged factorisation is kept while CG solves stay cheaper than the factor's average cost
// per solve, and renewed after a solve that cost more: a factor that has aged must not be kept
// for ever (each CG iteration costs about a triangular solve pair), nor a fresh one thrown away.
TEST_CASE("lagged factor is kept while cheap and renewed once it has aged", "[twin][solver]") {
  const ShellModel model(make_rectangular_sheet(0.4, 0.3, 0.04), Material{});
  std::vector<char> fixed(model.vertex_count(), 0);
  fixed[0] = fixed[5] = fixed[model.vertex_count() - 1] = 1;  // three corners stop rigid motion
  const DofMap dofs(fixed);
  const Objective objective(model.potential_terms());
  SheetPlacement placement;
  const VecX flat = place_flat(model.mesh(), placement);
  // A gently sagged state and one deformed a lot further from it, both smooth enough that the
  // projected Hessian is positive definite with the corners held.
  VecX near = flat, far = flat;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int v = 0; v < model.vertex_count(); ++v) {
    const Vec2 p = model.mesh().rest_uv[v];
    near[3 * v + 2] -= 0.01 * std::sin(3.0 * p.x()) * std::sin(4.0 * p.y());
    far[3 * v + 2] -= 0.02 * std::sin(9.0 * p.x()) * std::sin(7.0 * p.y()) + 0.0005 * u(rng);
  }
  LinearSolverOptions options;
  options.reuse_factorization = true;
  options.max_cg_iterations = 200;
  NewtonLinearSolver solver;
  solver.prepare(objective, dofs);
  auto solve = [&](const VecX& x, double tolerance) {
    VecX grad(x.size()), step;
    objective.evaluate(x, &grad, nullptr, HessianMode::kProjected);
    LinearSolveStats stats;
    REQUIRE(solver.solve(objective, x, gather_free(dofs, grad), HessianMode::kProjected, options,
                         tolerance, step, stats));
    return stats;
  };

  CHECK(solve(near, 1e-2).factorizations == 1);  // nothing to reuse yet
  const LinearSolveStats same = solve(near, 1e-2);  // the factor is this very matrix's
  CHECK(same.factorizations == 0);
  CHECK(same.cg_iterations <= 1);
  const LinearSolveStats aged = solve(far, 1e-6);
  CHECK(aged.factorizations == 0);  // CG still solved it with the old factor...
  // ...but at more than the cycle's average cost per solve so far:
  // (factorisation + (1 + same) + (1 + aged)) / 3 in CG iterations.
  REQUIRE(1.0 + aged.cg_iterations >
          (options.factorization_cost_in_cg_iterations + 1.0 + 1.0 + same.cg_iterations + 1.0 +
           aged.cg_iterations) / 3.0);
  CHECK(solve(far, 1e-2).factorizations == 1);  // so the next solve renews the factor
  CHECK(solve(far, 1e-2).factorizations == 0);  // and the renewed one is kept
}

}  // namespace
}  // namespace twin
