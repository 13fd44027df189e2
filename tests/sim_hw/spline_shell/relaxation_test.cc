// Relaxing a carried shape by preconditioned L-BFGS before Newton's method reaches the same
// equilibrium as Newton's method alone, with fewer factorisations than iterations; a fall (with
// damping) is left to Newton's pseudo-time.

#include <catch2/catch.hpp>

#include "sim_hw/spline_shell/shell_equilibrium.h"
#include "tests/sim_hw/spline_shell/shell_fixtures.h"

namespace ss = sim_hw::spline_shell;

TEST_CASE("spline shell: a carried shape relaxed by L-BFGS settles where Newton's method puts it", "[spline_shell]") {
  const double W = 0.3, H = 0.25;
  const std::vector<ss::SquareJaw> jaws = {ss::square_jaw("A", ss::Vec2(0.06, 0.22), 0.015, W, H),
                                           ss::square_jaw("B", ss::Vec2(0.24, 0.22), 0.015, W, H)};
  const ss::KnotVector ku = ss::jaw_knots(3, W, 0, jaws, 0.04, 0.01), kv = ss::jaw_knots(3, H, 1, jaws, 0.04, 0.01);
  const ss::ShellModel coarse(ss::SplinePatch(ku, kv), shell_fixtures::composite());
  const ss::ShellModel fine(ss::SplinePatch(ss::refined(ku), ss::refined(kv)), shell_fixtures::composite());
  // Jaws 4 cm closer than the material between them: the sheet sags into a fold.
  ss::ShellHolds holds;
  holds.jaws.push_back({jaws[0], ss::Vec3(0.08, 0.22, 0.0), Eigen::Matrix3d::Identity()});
  holds.jaws.push_back({jaws[1], ss::Vec3(0.22, 0.22, 0.0), Eigen::Matrix3d::Identity()});
  ss::VecX x = coarse.patch().flat_positions();
  ss::ShellSolveOptions fall;
  fall.initial_damping_1_s2 = 100.0;
  fall.relax_to_force = 1e-6;  // ignored: damped
  const ss::ShellSolveReport fell = ss::solve_shell(coarse, holds, x, fall);
  REQUIRE(fell.converged);
  CHECK(fell.relaxation_iterations == 0);

  const ss::VecX carried = ss::refine_controls(coarse.patch(), x, fine.patch());
  ss::VecX by_newton = carried, relaxed = carried;
  const ss::ShellSolveReport newton = ss::solve_shell(fine, holds, by_newton);
  ss::ShellSolveOptions relax;
  relax.relax_to_force = 1e-6;
  const ss::ShellSolveReport lbfgs = ss::solve_shell(fine, holds, relaxed, relax);
  REQUIRE(newton.converged);
  REQUIRE(lbfgs.converged);
  CHECK(newton.relaxation_iterations == 0);
  CHECK(lbfgs.relaxation_iterations > 0);
  CHECK(lbfgs.factorizations < lbfgs.relaxation_iterations + lbfgs.iterations);
  CHECK((relaxed - by_newton).lpNorm<Eigen::Infinity>() < 1e-8);
  CHECK(lbfgs.energy_J == Approx(newton.energy_J).epsilon(1e-12));
}
