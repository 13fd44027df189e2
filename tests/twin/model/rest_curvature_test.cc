// Rest curvature (roll set) in the hinge bending: rest angles from the curvature tensor K0
// (rest_curvature.h), applied by the ShellModel from the material's effects.
//  - a sheet wrapped on a cylinder with K0 equal to the cylinder's curvature stores almost no
//    bending energy and feels almost no bending force, along u, v, the diagonal and curled
//    either way;
//  - rest angles are the dihedral angles of the wrapped hinges, to first order, and linear in K0;
//  - the bending term's gradient and Hessian with rest angles (and stiffening) match finite
//    differences;
//  - a clamped sheet with a roll set settles visibly differently from a flat-at-rest one.

#include "twin/model/rest_curvature.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "tests/support/random_states.h"
#include "tests/support/term_check.h"
#include "twin/model/bending_term.h"
#include "twin/model/dihedral_angle.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace twin {
namespace {

constexpr double kRigidity_Nm = 1e-3;

CurvatureTensor cylinder_tensor(double angle_rad, double kappa_1_m) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {kappa_1_m * c * c, kappa_1_m * s * s, kappa_1_m * c * s};
}

double energy(const EnergyTerm& term, const VecX& x, VecX* grad = nullptr) {
  if (grad) *grad = VecX::Zero(x.size());
  return term.evaluate(x, grad, nullptr, HessianMode::kExact);
}

TEST_CASE("a sheet wrapped on a cylinder matching its rest curvature stores no bending energy",
          "[twin][effects]") {
  const SheetMesh mesh = make_rectangular_sheet(0.4, 0.3, 0.03);
  BendingTerm term(mesh, kRigidity_Nm, kRigidity_Nm);
  for (double angle : {0.0, M_PI / 2.0, M_PI / 4.0, 2.0 * M_PI / 3.0}) {
    for (double kappa : {5.0, -3.0}) {
      const VecX x = wrap_on_cylinder(mesh, angle, kappa);
      term.set_rest_curvature({});
      VecX g_flat, g_set;
      const double e_flat = energy(term, x, &g_flat);
      term.set_rest_curvature(cylinder_tensor(angle, kappa));
      const double e_set = energy(term, x, &g_set);
      INFO("angle " << angle << " rad, kappa " << kappa << " 1/m: energy " << e_set << " J with "
                    << "the roll set, " << e_flat << " J without; force ratio "
                    << g_set.norm() / g_flat.norm());
      CHECK(e_set / e_flat < 1e-3);  // measured below 1e-5
      CHECK(g_set.norm() / g_flat.norm() < 1e-2);
      // The continuum energy of the unset sheet, as a sanity check of the setting.
      CHECK(e_flat == Approx(0.5 * kRigidity_Nm * kappa * kappa * 0.4 * 0.3).epsilon(0.15));
    }
  }
}

TEST_CASE("rest angles are the first-order dihedral angles of the curved rest hinge",
          "[twin][effects]") {
  const SheetMesh mesh = make_rectangular_sheet(0.4, 0.3, 0.03);
  const auto hinges = build_hinges(mesh);
  const HingeCurvatureMap map(mesh, hinges);
  // A general tensor (twist included), small enough for the angles to be linear in it.
  const CurvatureTensor k{0.02, -0.01, 0.015};
  double worst = 0.0, largest = 0.0;
  for (int e = 0; e < map.hinge_count(); ++e) {
    // The surface's tangent plane at the hinge is horizontal: a tilted one would rotate the
    // hinge rigidly, which changes theta at second order only, but measurably.
    const Vec2 centre = 0.5 * (mesh.rest_uv[hinges[e].v[0]] + mesh.rest_uv[hinges[e].v[1]]);
    Vec12 xh;
    for (int j = 0; j < 4; ++j) {
      const Vec2 uv = mesh.rest_uv[hinges[e].v[j]] - centre;
      const double w = 0.5 * (k.uu_1_m * uv.x() * uv.x() + k.vv_1_m * uv.y() * uv.y()) +
                       k.uv_1_m * uv.x() * uv.y();
      xh.segment<3>(3 * j) = Vec3(uv.x(), uv.y(), w);
    }
    const double theta = dihedral_angle(xh, nullptr, nullptr);
    worst = std::max(worst, std::abs(theta - map.rest_angle(e, k)));
    largest = std::max(largest, std::abs(theta));
  }
  INFO("largest angle " << largest << " rad, largest difference " << worst << " rad");
  CHECK(largest > 1e-4);
  CHECK(worst < 1e-4 * largest);
  // Sign convention of dihedral_angle.h: curling towards the normal lifts the wings, theta < 0.
  CHECK(map.rest_angle(0, {1.0, 1.0, 0.0}) < 0.0);
  for (double t : map.across_lengths_m()) {
    CHECK(t > 0.5 * 0.03 * std::sqrt(3.0) / 2.0 * 0.5);  // about the hinge's width
    CHECK(t < 2.0 * 0.03);
  }
}

TEST_CASE("rest angles are linear in the rest curvature tensor", "[twin][effects]") {
  const SheetMesh mesh = make_rectangular_sheet(0.3, 0.2, 0.04);
  const HingeCurvatureMap map(mesh, build_hinges(mesh));
  const CurvatureTensor a{3.0, -1.0, 0.5}, b{-2.0, 4.0, 1.5};
  const double alpha = 0.7, beta = -1.3;
  const CurvatureTensor mix{alpha * a.uu_1_m + beta * b.uu_1_m, alpha * a.vv_1_m + beta * b.vv_1_m,
                            alpha * a.uv_1_m + beta * b.uv_1_m};
  const auto ta = map.rest_angles(a), tb = map.rest_angles(b), tm = map.rest_angles(mix);
  for (std::size_t e = 0; e < tm.size(); ++e) {
    CHECK(tm[e] == Approx(alpha * ta[e] + beta * tb[e]).margin(1e-14));
  }
  CHECK(map.rest_angles({}) == std::vector<double>(tm.size(), 0.0));
}

TEST_CASE("the ShellModel applies the bending effects of a material file, and only on change",
          "[twin][effects]") {
  // As a user writes it: the "effects" block of the material file (docs/file_formats.md, "Material file").
  nlohmann::json j = material_to_json(Material{});
  j["effects"] = nlohmann::json::parse(
      R"({"rest_curvature_1_m": {"uu": 4.0}, "bending_stiffening_m2": 0.03})");
  Material m = material_from_json(j, "roll.json");
  ShellModel model(make_rectangular_sheet(0.3, 0.2, 0.04), m);
  const auto expected = model.bending().curvature_map().rest_angles({4.0, 0.0, 0.0});
  for (std::size_t e = 0; e < expected.size(); ++e) {
    const HingeElement& h = model.bending().elements()[e];
    REQUIRE(h.rest_angle_rad == expected[e]);
    const double d = model.bending().stiffening_lengths_m()[e];
    REQUIRE(h.quartic_per_rad2 == Approx(0.03 / (2.0 * d * d)).epsilon(1e-15));
  }
  m.effects.bending_stiffening_m2 = 0.0;
  // Rest angles set by hand are replaced by the material's again on the next set_material.
  model.bending().set_rest_angles(std::vector<double>(expected.size(), 0.25));
  model.set_material(m);
  CHECK(model.bending().elements()[0].rest_angle_rad == expected[0]);
  m.effects.rest_curvature_uu_1_m = 0.0;
  model.set_material(m);
  for (const HingeElement& h : model.bending().elements()) {
    CHECK(h.rest_angle_rad == 0.0);
    CHECK(h.quartic_per_rad2 == 0.0);
  }
}

TEST_CASE("bending with rest angles and stiffening: gradient and Hessian match finite differences",
          "[twin][effects]") {
  const SheetMesh mesh = make_rectangular_sheet(0.12, 0.1, 0.04);
  BendingTerm term(mesh, 2e-3, 7e-4);
  term.set_rest_curvature({6.0, -3.0, 2.0});
  std::mt19937 rng(61);
  for (double beta : {0.0, 0.05}) {
    term.set_stiffening(beta);
    for (int trial = 0; trial < 4; ++trial) {
      const VecX x = testing::random_deformed(mesh.rest_uv, 0.05, 0.2, rng);
      const auto errors = testing::term_derivative_errors(term, x);
      INFO("beta " << beta << " m^2: " << errors.report());
      CHECK(errors.gradient < 1e-6);
      CHECK(errors.hessian < 1e-6);
    }
  }
}

TEST_CASE("a clamped sheet with a roll set settles visibly differently", "[twin][effects]") {
  Material m;
  m.surface_density_kg_m2 = 0.3;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 3000.0;
  // Stiff enough for a roll set to hold against gravity: the rest moment D K0 is a third of the
  // weight's moment at the clamps.
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 5e-3;
  ShellModel model(make_rectangular_sheet(0.4, 0.3, 0.03), m);
  // Held along the short edge u = 0 by two clamps, sticking out horizontally: a cantilever.
  const ClampSet clamps(model.mesh(), {{"a", Vec2(0.02, 0.05), 0.025}, {"b", Vec2(0.02, 0.25), 0.025}});
  const SheetPlacement placement{Vec3(0.0, 0.0, 1.0), Mat3::Identity()};
  std::vector<ClampPose> poses;
  for (int i = 0; i < clamps.size(); ++i) {
    poses.push_back({placement.to_world(clamps[i].spec().material_point_m), Mat3::Identity(), true});
  }
  auto settle = [&](double k_uu) {
    Material with = m;
    with.effects.rest_curvature_uu_1_m = k_uu;
    model.set_material(with);
    VecX x = place_flat(model.mesh(), placement);
    const SolveReport report = StaticSolver(model).solve(clamps, poses, x);
    INFO("K0_uu " << k_uu << " 1/m: " << report.brief());
    REQUIRE(report.usable());
    return x;
  };
  const VecX flat = settle(0.0), rolled_up = settle(10.0), rolled_down = settle(-10.0);
  // The free end (u = 0.4, mid-width): the flat-at-rest sheet droops; a positive roll set
  // (curling towards +z, the triangles' normal) lifts it and holds it further out, a negative
  // one curls it down and back under the clamps.
  int tip = 0;
  for (int i = 0; i < model.vertex_count(); ++i) {
    if ((model.mesh().rest_uv[i] - Vec2(0.4, 0.15)).norm() <
        (model.mesh().rest_uv[tip] - Vec2(0.4, 0.15)).norm()) {
      tip = i;
    }
  }
  INFO("tip (x, z): flat (" << flat(3 * tip) << ", " << flat(3 * tip + 2) << ") m, K0 +10: ("
                             << rolled_up(3 * tip) << ", " << rolled_up(3 * tip + 2)
                             << ") m, K0 -10: (" << rolled_down(3 * tip) << ", "
                             << rolled_down(3 * tip + 2) << ") m");
  CHECK(rolled_up(3 * tip + 2) > flat(3 * tip + 2) + 0.05);  // measured +0.11 m
  CHECK(rolled_up(3 * tip) > flat(3 * tip) + 0.05);          // measured +0.15 m
  CHECK(rolled_down(3 * tip) < flat(3 * tip) - 0.05);        // measured -0.16 m
}

}  // namespace
}  // namespace twin
