#include "twin/model/membrane_energy.h"

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>

#include "tests/support/finite_difference.h"
#include "tests/support/random_states.h"
#include "twin/model/material.h"

namespace twin::membrane_energy_test {
namespace {

using testing::finite_difference_errors;

Mat3 anisotropic_stiffness() {
  Material m;
  m.tensile_stiffness_u_N_m = 8000.0;
  m.tensile_stiffness_v_N_m = 3000.0;
  m.shear_stiffness_N_m = 700.0;
  m.poisson_ratio = 0.3;
  return m.membrane_stiffness();
}

SheetMesh random_triangle(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  SheetMesh mesh;
  mesh.rest_uv = {Vec2(0, 0) + Vec2(u(rng), u(rng)), Vec2(0.1, 0) + Vec2(u(rng), u(rng)),
                  Vec2(0.04, 0.09) + Vec2(u(rng), u(rng))};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

testing::EnergyFunction membrane_function(const MembraneElement& e, const Mat3& c,
                                          HessianMode mode) {
  return [e, c, mode](const VecX& x, VecX* g, Eigen::MatrixXd* h) {
    Vec9 ge;
    Mat9 he;
    const double energy = membrane_energy(e, c, x, g ? &ge : nullptr, h ? &he : nullptr, mode);
    if (g) *g = ge;
    if (h) *h = he;
    return energy;
  };
}

TEST_CASE("membrane gradient and Hessian match finite differences", "[twin][energy]") {
  std::mt19937 rng(7);
  const Mat3 c = anisotropic_stiffness();
  for (int trial = 0; trial < 20; ++trial) {
    const SheetMesh mesh = random_triangle(rng);
    const MembraneElement e = make_membrane_element(mesh, 0);
    const VecX x = testing::random_deformed(mesh.rest_uv, 0.1, 0.2, rng);
    const auto errors =
        finite_difference_errors(membrane_function(e, c, HessianMode::kExact), x, 1e-7);
    INFO(errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-6);
  }
}

TEST_CASE("membrane strain is Green-Lagrange in the material frame", "[twin][energy]") {
  SheetMesh mesh;
  mesh.rest_uv = {Vec2(0, 0), Vec2(0.1, 0), Vec2(0, 0.1)};
  mesh.triangles = {{0, 1, 2}};
  const MembraneElement e = make_membrane_element(mesh, 0);
  CHECK(e.rest_area_m2 == Approx(0.005));
  // Stretch 1.1 along u, 0.9 along v, and shear v toward u by 0.05.
  Vec9 x;
  x << 0, 0, 0, 0.11, 0, 0, 0.005, 0.09, 0;
  const Vec3 eps = membrane_strain(e, x, nullptr);
  CHECK(eps(0) == Approx(0.5 * (1.1 * 1.1 - 1.0)));
  CHECK(eps(1) == Approx(0.5 * (0.05 * 0.05 + 0.9 * 0.9 - 1.0)));
  CHECK(eps(2) == Approx(1.1 * 0.05));
}

TEST_CASE("projected membrane Hessian is positive semi-definite under compression",
          "[twin][energy]") {
  std::mt19937 rng(11);
  const Mat3 c = anisotropic_stiffness();
  const SheetMesh mesh = random_triangle(rng);
  const MembraneElement e = make_membrane_element(mesh, 0);
  Vec9 x;
  for (int k = 0; k < 3; ++k) x.segment<3>(3 * k) = Vec3(0.7 * mesh.rest_uv[k].x(), 0.8 * mesh.rest_uv[k].y(), 0.0);
  Mat9 exact, projected;
  membrane_energy(e, c, x, nullptr, &exact, HessianMode::kExact);
  membrane_energy(e, c, x, nullptr, &projected, HessianMode::kProjected);
  CHECK(Eigen::SelfAdjointEigenSolver<Mat9>(exact).eigenvalues().minCoeff() < -1e-3);
  CHECK(Eigen::SelfAdjointEigenSolver<Mat9>(projected).eigenvalues().minCoeff() > -1e-9);
}

TEST_CASE("the checker catches a planted derivative bug", "[twin][energy][checker]") {
  std::mt19937 rng(3);
  const Mat3 c = anisotropic_stiffness();
  const SheetMesh mesh = random_triangle(rng);
  const MembraneElement e = make_membrane_element(mesh, 0);
  const VecX x = testing::random_deformed(mesh.rest_uv, 0.1, 0.2, rng);
  // Bug 1: the geometric stiffness left out (a classic mistake), via the projected Hessian of a
  // compressed state. Bug 2: a gradient off by 0.1 percent.
  const VecX compressed = 0.8 * x;
  const auto missing_geometric =
      finite_difference_errors(membrane_function(e, c, HessianMode::kProjected), compressed, 1e-7);
  CHECK(missing_geometric.hessian > 1e-3);
  auto scaled = [&](const VecX& y, VecX* g, Eigen::MatrixXd* h) {
    const double energy = membrane_function(e, c, HessianMode::kExact)(y, g, h);
    if (g) *g *= 1.001;
    return energy;
  };
  const auto wrong_gradient = finite_difference_errors(scaled, x, 1e-7);
  CHECK(wrong_gradient.gradient > 1e-4);
}

}  // namespace
}  // namespace twin::membrane_energy_test
