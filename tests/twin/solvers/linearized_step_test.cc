#include <catch2/catch.hpp>

#include "twin/solvers/implicit_stepper.h"
#include "twin/model/objective.h"

namespace twin {
namespace {

// Linearised backward Euler (one Newton iteration per step, the paper engine's scheme): every
// step is usable and reports its fixed iteration budget, and the damped sheet loses energy.
// Unlike the converged step it only guarantees that its incremental potential fell, so the
// total energy may rise slightly in a step (measured up to 2e-4 relative); it must not grow.
TEST_CASE("linearised implicit steps are usable and dissipate", "[twin][physics]") {
  Material material;
  material.tensile_viscosity_Ns_m = material.shear_viscosity_Ns_m = 2.0;
  const ShellModel model(make_rectangular_sheet(0.4, 0.3, 0.04), material);
  const ClampSet clamps(model.mesh(), {{"A", Vec2(0.02, 0.28), 0.02}, {"B", Vec2(0.38, 0.28), 0.02}});
  SheetPlacement placement;
  placement.origin_m = Vec3(0, 0, 1);
  VecX x = place_flat(model.mesh(), placement);
  VecX v = VecX::Zero(x.size());
  std::vector<ClampPose> poses(2);
  for (int i = 0; i < 2; ++i) poses[i].position_m = placement.to_world(clamps[i].spec().material_point_m);
  const Objective potential(model.potential_terms());
  auto total_energy = [&] {
    return potential.evaluate(x, nullptr, nullptr, HessianMode::kExact) + kinetic_energy(model, v);
  };
  ImplicitStepper stepper(model);
  const double start = total_energy();
  double previous = start;
  for (int s = 0; s < 40; ++s) {
    const SolveReport r = stepper.step(x, v, 0.01, clamps, poses, linearized_step_options());
    INFO("step " << s << ": " << r.brief());
    REQUIRE(r.usable());
    CHECK(r.iterations == stepper.last_substeps());  // one Newton iteration per (sub-)step
    const double now = total_energy();
    CHECK(now <= previous + 1e-3 * std::abs(previous));
    previous = now;
  }
  CHECK(previous < start - 0.01);  // the hanging sheet fell and lost energy, J
  CHECK(x.allFinite());
}

}  // namespace
}  // namespace twin
