#include <catch2/catch.hpp>
#include <random>

#include "tests/support/term_check.h"
#include "tests/support/random_states.h"
#include "twin/model/inertia_term.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/shell_model.h"
#include "twin/model/viscosity_term.h"

namespace twin {
namespace {

TEST_CASE("inertia and viscosity terms match finite differences", "[twin][energy]") {
  Material material;
  material.tensile_viscosity_Ns_m = 3.0;
  material.shear_viscosity_Ns_m = 1.5;
  material.mass_damping_1_s = 0.4;
  const ShellModel model(make_rectangular_sheet(0.2, 0.1, 0.05), material);
  std::mt19937 rng(4);
  const VecX x0 = testing::random_deformed(model.mesh().rest_uv, 0.2, 0.05, rng);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VecX v0(x0.size()), wiggle(x0.size());
  for (int i = 0; i < x0.size(); ++i) {
    v0(i) = unit(rng);
    wiggle(i) = unit(rng);
  }
  const VecX x = x0 + 0.01 * v0 + 1e-3 * wiggle;

  InertiaTerm inertia(model.vertex_masses_kg(), material.mass_damping_1_s);
  inertia.set_step(x0, v0, 0.01);
  const auto inertia_errors = testing::term_derivative_errors(inertia, x);
  INFO("inertia " << inertia_errors.report());
  CHECK(inertia_errors.gradient < 1e-6);
  CHECK(inertia_errors.hessian < 1e-6);

  ViscosityTerm viscosity(model.membrane().elements(), model.vertex_count(),
                          material.tensile_viscosity_Ns_m, material.shear_viscosity_Ns_m);
  viscosity.set_step(x0, 0.01);
  const auto viscosity_errors = testing::term_derivative_errors(viscosity, x);
  INFO("viscosity " << viscosity_errors.report());
  CHECK(viscosity_errors.gradient < 1e-6);
  CHECK(viscosity_errors.hessian < 1e-6);
}

TEST_CASE("viscous force is the strain-rate stress of the paper", "[twin][energy]") {
  // For a velocity v, the viscous force on a triangle is -A0 J^T C' J v (paper Eq. 9).
  Material material;
  material.tensile_viscosity_Ns_m = 2.0;
  material.shear_viscosity_Ns_m = 0.5;
  const ShellModel model(make_rectangular_sheet(0.1, 0.1, 0.1), material);
  std::mt19937 rng(8);
  const VecX x0 = testing::random_deformed(model.mesh().rest_uv, 0.1, 0.05, rng);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VecX v(x0.size());
  for (int i = 0; i < x0.size(); ++i) v(i) = unit(rng);
  const double dt = 0.01;
  ViscosityTerm viscosity(model.membrane().elements(), model.vertex_count(), 2.0, 0.5);
  viscosity.set_step(x0, dt);
  VecX grad = VecX::Zero(x0.size());
  viscosity.evaluate(x0 + dt * v, &grad, nullptr, HessianMode::kExact);
  VecX expected = VecX::Zero(x0.size());
  for (const MembraneElement& e : model.membrane().elements()) {
    Vec9 xe, ve;
    for (int k = 0; k < 3; ++k) {
      xe.segment<3>(3 * k) = x0.segment<3>(3 * e.v[k]);
      ve.segment<3>(3 * k) = v.segment<3>(3 * e.v[k]);
    }
    StrainJacobian j;
    membrane_strain(e, xe, &j);
    const Vec3 strain_rate = j * ve;
    const Vec9 f = e.rest_area_m2 * j.transpose() * Vec3(2.0, 2.0, 0.5).asDiagonal() * strain_rate;
    for (int k = 0; k < 3; ++k) expected.segment<3>(3 * e.v[k]) += f.segment<3>(3 * k);
  }
  CHECK((grad - expected).norm() < 1e-12 * expected.norm());
}

}  // namespace
}  // namespace twin
