#include "twin/model/shell_model.h"

#include <catch2/catch.hpp>

#include <algorithm>

#include "twin/solvers/implicit_stepper.h"
#include "twin/mesh/mesh_refinement.h"
#include "twin/model/viscosity_term.h"

namespace twin {
namespace {

TEST_CASE("changing the material updates every term in place", "[twin][model]") {
  Material material;
  ShellModel model(make_rectangular_sheet(0.3, 0.2, 0.03), material);
  const VecX x = place_flat(model.mesh(), SheetPlacement{Vec3(0, 0, 2.0), Mat3::Identity()});
  const double mass = model.total_mass_kg();
  CHECK(mass == Approx(0.3 * 0.06));
  const double gravity_energy = model.gravity().evaluate(x, nullptr, nullptr, HessianMode::kExact);

  Material heavier = material;
  heavier.surface_density_kg_m2 *= 2.0;
  heavier.bending_rigidity_u_Nm *= 3.0;
  heavier.bending_rigidity_v_Nm *= 3.0;
  model.set_material(heavier);
  CHECK(model.total_mass_kg() == Approx(2.0 * mass));
  CHECK(model.gravity().evaluate(x, nullptr, nullptr, HessianMode::kExact) ==
        Approx(2.0 * gravity_energy));
  CHECK(model.bending().elements()[0].stiffness_Nm > 0.0);

  // A material the mesh cannot represent is refused and leaves the model as it was.
  const double k0 = model.bending().elements()[0].stiffness_Nm;
  Material extreme = heavier;
  extreme.bending_rigidity_v_Nm = 1000.0 * extreme.bending_rigidity_u_Nm;
  CHECK_THROWS(model.set_material(extreme));
  CHECK(model.total_mass_kg() == Approx(2.0 * mass));
  CHECK(model.bending().elements()[0].stiffness_Nm == k0);
  Material negative = heavier;
  negative.shear_stiffness_N_m = -1.0;
  CHECK_THROWS_WITH(model.set_material(negative), Catch::Contains("shear_stiffness_N_m"));
}

TEST_CASE("the plate bending model replaces the hinges in the energy and keeps its model", "[twin][model]") {
  Material material;
  material.bending_model = Material::BendingModel::kPlate;
  ShellModel model(make_rectangular_sheet(0.3, 0.2, 0.03), material);
  REQUIRE(model.plate_bending() != nullptr);
  const auto terms = model.potential_terms();
  CHECK(std::find(terms.begin(), terms.end(), model.plate_bending()) != terms.end());
  CHECK(std::find(terms.begin(), terms.end(), &model.bending()) == terms.end());
  CHECK(model.plate_bending()->rigidity()(2, 2) == Approx(0.35e-3));  // Huber, nu = 0.3

  Material stiffer = material;
  stiffer.bending_rigidity_u_Nm = stiffer.bending_rigidity_v_Nm = 2e-3;
  model.set_material(stiffer);
  CHECK(model.plate_bending()->rigidity()(0, 0) == 2e-3);
  CHECK(model.plate_bending()->rigidity()(2, 2) == Approx(0.7e-3));
  Material hinge = stiffer;
  hinge.bending_model = Material::BendingModel::kHinge;
  CHECK_THROWS_WITH(model.set_material(hinge), Catch::Contains("bending model"));
  CHECK(model.material().bending_model == Material::BendingModel::kPlate);
}

TEST_CASE("a uniformly refined mesh gets the quadratic membrane, which follows the material",
          "[twin][model]") {
  Material material;
  ShellModel linear(make_rectangular_sheet(0.3, 0.2, 0.03), material);
  ShellModel quadratic(refine_uniformly(make_rectangular_sheet(0.3, 0.2, 0.06)), material);
  CHECK(linear.membrane_energy().name() == "membrane");
  CHECK(quadratic.membrane_energy().name() == "membrane (quadratic)");
  CHECK(quadratic.potential_terms().front() == &quadratic.membrane_energy());
  // Stretched 2 % along u: both give the exact energy of a uniform strain; doubling the
  // stiffnesses doubles it.
  VecX x = place_flat(quadratic.mesh(), SheetPlacement{Vec3(0, 0, 1.0), Mat3::Identity()});
  for (int i = 0; i < quadratic.vertex_count(); ++i) x(3 * i) *= 1.02;
  const double e1 = quadratic.membrane_energy().evaluate(x, nullptr, nullptr, HessianMode::kExact);
  // The linear triangles of the same mesh (what the viscosity acts on) agree.
  CHECK(e1 == Approx(quadratic.membrane().evaluate(x, nullptr, nullptr, HessianMode::kExact)).epsilon(1e-12));
  Material stiffer = material;
  stiffer.tensile_stiffness_u_N_m *= 2.0;
  stiffer.tensile_stiffness_v_N_m *= 2.0;
  stiffer.shear_stiffness_N_m *= 2.0;
  quadratic.set_material(stiffer);
  CHECK(quadratic.membrane_energy().evaluate(x, nullptr, nullptr, HessianMode::kExact) == Approx(2.0 * e1));
}

TEST_CASE("viscosity switched off leaves no damping behind", "[twin][model]") {
  Material material;
  const ShellModel model(make_rectangular_sheet(0.2, 0.1, 0.05), material);
  ViscosityTerm viscosity(model.membrane().elements(), model.vertex_count(), 3.0, 1.5);
  VecX x0 = place_flat(model.mesh(), SheetPlacement());
  for (int i = 0; i < x0.size(); i += 3) x0(i) *= 1.01;  // a stretched start, so J0 != 0
  VecX x1 = x0;
  x1(0) += 1e-3;
  viscosity.set_step(x0, 0.01);
  CHECK(viscosity.evaluate(x1, nullptr, nullptr, HessianMode::kExact) > 0.0);
  viscosity.set_viscosity(0.0, 0.0);
  viscosity.set_step(x0, 0.01);
  CHECK(viscosity.evaluate(x1, nullptr, nullptr, HessianMode::kExact) == 0.0);
}

}  // namespace
}  // namespace twin
