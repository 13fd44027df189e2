// Marker mass and viscoelastic relaxation in the ShellModel (model_effects.h): where the masses
// go, that gravity stays exact and linear in the marker mass, and that the load age scales the
// stiffness terms by the relaxation factor (with their derivatives still exact).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "tests/support/term_check.h"
#include "twin/model/clamp.h"
#include "twin/model/dof_map.h"
#include "twin/solvers/equilibrium_sensitivity.h"
#include "twin/model/shell_model.h"

namespace twin {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A crumpled state of a 0.3 x 0.2 m sheet, 1 m up (seeded).
VecX crumpled(const ShellModel& model, unsigned seed) {
  VecX x = place_flat(model.mesh(), SheetPlacement{Vec3(0.1, -0.2, 1.0), Mat3::Identity()});
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 3e-3);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += noise(rng);
  return x;
}

std::vector<Vec2> some_markers() {
  return {Vec2(0.05, 0.05), Vec2(0.123, 0.071), Vec2(0.25, 0.15), Vec2(0.3, 0.2), Vec2(0.0, 0.1)};
}

TEST_CASE("marker masses sit where the markers are glued and only there", "[twin][trial_effects]") {
  Material material;
  material.effects.marker_mass_kg = 0.002;
  ShellModel model(make_rectangular_sheet(0.3, 0.2, 0.03), material);
  const double sheet_kg = 0.3 * 0.3 * 0.2;
  // No markers (the cell's ply): the effect has nothing to act on.
  CHECK(model.total_mass_kg() == Approx(sheet_kg).epsilon(1e-12));
  const MaterialPointMap markers(model.mesh(), some_markers());
  model.set_marker_points(markers);
  CHECK(model.total_mass_kg() == Approx(sheet_kg + 5 * 0.002).epsilon(1e-12));

  // Gravity's energy is that of the sheet plus that of point masses at the markers' places.
  const VecX x = crumpled(model, 3);
  ShellModel bare(make_rectangular_sheet(0.3, 0.2, 0.03), Material{});
  const Vec3 g = model.gravity().gravity();
  double expected_J = bare.gravity().evaluate(x, nullptr, nullptr, HessianMode::kExact);
  for (const Vec3& p : markers.positions(x)) expected_J -= 0.002 * g.dot(p);
  CHECK(model.gravity().evaluate(x, nullptr, nullptr, HessianMode::kExact) == Approx(expected_J).epsilon(1e-12));
  const testing::DerivativeErrors errors = testing::term_derivative_errors(model.gravity(), x);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-7);
  CHECK(errors.hessian < 1e-7);

  // Changing the material keeps the markers; a zero marker mass removes their weight again.
  Material heavier = material;
  heavier.effects.marker_mass_kg = 0.004;
  model.set_material(heavier);
  CHECK(model.total_mass_kg() == Approx(sheet_kg + 5 * 0.004).epsilon(1e-12));
  model.set_material(Material{});
  CHECK(model.total_mass_kg() == Approx(sheet_kg).epsilon(1e-12));
  // Vertex ids out of range are refused.
  MaterialPointLocation bad = markers.location(0);
  bad.vertices[1] = model.vertex_count();
  CHECK_THROWS_WITH(model.set_marker_points(std::vector<MaterialPointLocation>{bad}),
                    Catch::Contains("marker 0") && Catch::Contains("vertex"));
}

TEST_CASE("the force derivative in the marker mass is the markers' weight, exactly", "[twin][trial_effects]") {
  ShellModel model(make_rectangular_sheet(0.3, 0.2, 0.03), Material{});
  const MaterialPointMap markers(model.mesh(), some_markers());
  model.set_marker_points(markers);
  const VecX x = crumpled(model, 4);
  std::vector<char> held(model.vertex_count(), 0);
  held[0] = 1;
  const DofMap dofs(held);
  // Expected: d(grad E)/dm = -g per unit weight at each marker's vertices.
  VecX expected = VecX::Zero(x.size());
  for (int i = 0; i < markers.size(); ++i) {
    const MaterialPointLocation& at = markers.location(i);
    for (int k = 0; k < 3; ++k) expected.segment<3>(3 * at.vertices[k]) -= at.weights(k) * model.gravity().gravity();
  }
  expected.segment<3>(0).setZero();
  for (double at_kg : {0.0, 0.003}) {
    Material m;
    m.effects.marker_mass_kg = at_kg;
    model.set_material(m);
    const VecX d = force_parameter_derivative(model, dofs, x, MaterialParameter::kMarkerMass);
    INFO("marker mass " << at_kg << " kg");
    CHECK((d - expected).norm() < 1e-8 * expected.norm());
    CHECK(model.material().effects.marker_mass_kg == at_kg);  // restored
  }
}

TEST_CASE("the load age scales the stiffness terms by the relaxation factor", "[twin][trial_effects]") {
  Material material;
  material.tensile_stiffness_v_N_m = 3000.0;
  material.bending_rigidity_v_Nm = 2e-3;
  material.effects.relaxation_fraction = 0.4;
  material.effects.relaxation_time_s = 100.0;
  ShellModel model(make_rectangular_sheet(0.3, 0.2, 0.03), material);
  Material plain = material;
  plain.effects = ModelEffects{};
  ShellModel reference(make_rectangular_sheet(0.3, 0.2, 0.03), plain);
  const VecX x = crumpled(model, 5);
  const auto energies = [&](const ShellModel& m) {
    return std::array<double, 3>{m.membrane().evaluate(x, nullptr, nullptr, HessianMode::kExact),
                                 m.bending().evaluate(x, nullptr, nullptr, HessianMode::kExact),
                                 m.gravity().evaluate(x, nullptr, nullptr, HessianMode::kExact)};
  };
  const std::array<double, 3> base = energies(reference);
  // Unknown age (the default): fully relaxed. Age 0: the material's own stiffness.
  CHECK(std::isnan(model.load_age_s()));
  for (double age_s : {kNaN, 0.0, 30.0, 100.0, 1e5}) {
    model.set_load_age_s(age_s);
    const double factor = std::isnan(age_s) ? 0.6 : 1.0 - 0.4 * (1.0 - std::exp(-age_s / 100.0));
    INFO("age " << age_s << " s");
    CHECK(model.stiffness_factor() == Approx(factor).epsilon(1e-14));
    const std::array<double, 3> e = energies(model);
    CHECK(e[0] == Approx(factor * base[0]).epsilon(1e-12));
    CHECK(e[1] == Approx(factor * base[1]).epsilon(1e-12));
    CHECK(e[2] == Approx(base[2]).epsilon(1e-12));  // weight does not relax
  }
  // The age survives a change of material, and the derivatives stay exact at a partial age.
  model.set_load_age_s(30.0);
  Material other = material;
  other.effects.relaxation_fraction = 0.2;
  model.set_material(other);
  CHECK(model.load_age_s() == 30.0);
  CHECK(model.stiffness_factor() == Approx(1.0 - 0.2 * (1.0 - std::exp(-0.3))).epsilon(1e-14));
  for (const EnergyTerm* term : {static_cast<const EnergyTerm*>(&model.membrane()),
                                 static_cast<const EnergyTerm*>(&model.bending())}) {
    const testing::DerivativeErrors errors = testing::term_derivative_errors(*term, x);
    INFO(term->name() << ": " << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-5);
  }
  CHECK_THROWS_WITH(model.set_load_age_s(-1.0), Catch::Contains("age") && Catch::Contains("-1"));
}

}  // namespace
}  // namespace twin
