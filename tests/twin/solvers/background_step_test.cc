#include <catch2/catch.hpp>

#include <cmath>

#include "twin/solvers/implicit_stepper.h"
#include "twin/solvers/static_solver.h"
#include "tests/support/vertex_distance.h"

namespace twin {
namespace {

// A sheet hanging from two clamps, one of which circles (2 cm radius, 1 s per turn), stepped
// with linearised backward Euler at dt 10 ms.
struct SwingingSheet {
  ShellModel model{make_rectangular_sheet(0.4, 0.3, 0.03), Material{}};
  ClampSet clamps{model.mesh(), {{"A", Vec2(0.02, 0.28), 0.02}, {"B", Vec2(0.38, 0.28), 0.02}}};
  SheetPlacement placement;
  VecX x0, v0;
  SwingingSheet() {
    placement.origin_m = Vec3(0, 0, 1);
    x0 = place_flat(model.mesh(), placement);
    v0 = VecX::Zero(x0.size());
  }
  std::vector<ClampPose> poses(double t_s, bool moving) const {
    std::vector<ClampPose> p(2);
    for (int i = 0; i < 2; ++i) p[i].position_m = placement.to_world(clamps[i].spec().material_point_m);
    if (moving) p[1].position_m += 0.02 * Vec3(std::cos(2 * M_PI * t_s) - 1.0, 0.0, std::sin(2 * M_PI * t_s));
    return p;
  }
};

using testing_support::largest_vertex_distance;

// The background-factorised step is CG with the factor of a predicted Hessian: from the same
// state it must land where the exactly solved step lands, within 0.1 mm per vertex (its CG
// bound is 0.01 mm), on a sheet that falls, swings and is pulled round by a circling clamp.
TEST_CASE("background-factorised steps agree with exactly solved steps", "[twin][solver]") {
  SwingingSheet sheet;
  StepOptions exact = linearized_step_options();
  exact.newton.linear.reuse_factorization = false;  // a factorisation of each step's own Hessian
  ImplicitStepper background(sheet.model), reference(sheet.model);
  VecX x = sheet.x0, v = sheet.v0;
  int cg = 0, factorizations = 0;
  double largest = 0.0;
  // (Each step also hands the next one's Hessian to the worker: the clamp moves.)
  for (int s = 0; s < 60; ++s) {
    const std::vector<ClampPose> poses = sheet.poses(0.01 * (s + 1), true);
    VecX x_ref = x, v_ref = v;
    REQUIRE(reference.step(x_ref, v_ref, 0.01, sheet.clamps, poses, exact).usable());
    const SolveReport r = background.step(x, v, 0.01, sheet.clamps, poses, background_linearized_step_options());
    INFO("step " << s << ": " << r.brief());
    REQUIRE(r.usable());
    cg += r.cg_iterations;
    factorizations += r.factorizations;
    largest = std::max(largest, largest_vertex_distance(x, x_ref));
    x = x_ref;  // both go on from the exact state
    v = v_ref;
  }
  INFO("largest vertex distance " << 1e3 * largest << " mm, " << cg << " CG iterations, "
       << factorizations << " factorisations waited for");
  CHECK(largest < 1e-4);
  // The first step has nothing to precondition with; later ones use the worker's factors.
  CHECK(factorizations < 10);
  CHECK(background.background_factorizations() == 60);
}

// Each step waits for the factor its predecessor predicted, so the results do not depend on
// how fast the worker is: two runs give the same bits.
TEST_CASE("background-factorised steps do not depend on timing", "[twin][solver]") {
  SwingingSheet sheet;
  auto run = [&] {
    ImplicitStepper stepper(sheet.model);
    VecX x = sheet.x0, v = sheet.v0;
    for (int s = 0; s < 30; ++s) {
      REQUIRE(stepper.step(x, v, 0.01, sheet.clamps, sheet.poses(0.01 * (s + 1), true),
                           background_linearized_step_options()).usable());
    }
    return x;
  };
  const VecX first = run(), second = run();
  CHECK((first - second).cwiseAbs().maxCoeff() == 0.0);
}

// At rest (clamps still, CG content with the factor at hand) no factorisation is made at all.
TEST_CASE("a sheet at rest costs the background stepper no factorisation", "[twin][solver]") {
  SwingingSheet sheet;
  const std::vector<ClampPose> still = sheet.poses(0.0, false);
  VecX x = sheet.x0, v = sheet.v0;
  REQUIRE(StaticSolver(sheet.model).solve(sheet.clamps, still, x).usable());
  ImplicitStepper stepper(sheet.model);
  // (At equilibrium a step may need no linear solve at all.)
  for (int s = 0; s < 3; ++s) {
    REQUIRE(stepper.step(x, v, 0.01, sheet.clamps, still, background_linearized_step_options()).usable());
  }
  const int submitted = stepper.background_factorizations();
  int cg = 0, factorizations = 0;
  for (int s = 0; s < 10; ++s) {
    const SolveReport r = stepper.step(x, v, 0.01, sheet.clamps, still, background_linearized_step_options());
    REQUIRE(r.usable());
    cg += r.cg_iterations;
    factorizations += r.factorizations;
  }
  INFO(cg << " CG iterations");
  CHECK(factorizations == 0);
  CHECK(stepper.background_factorizations() == submitted);
  // Once it moves again, every step hands over the next one's Hessian.
  for (int s = 0; s < 5; ++s) {
    REQUIRE(stepper.step(x, v, 0.01, sheet.clamps, sheet.poses(0.01 * (s + 1), true),
                         background_linearized_step_options()).usable());
  }
  CHECK(stepper.background_factorizations() == submitted + 5);
}

}  // namespace
}  // namespace twin
