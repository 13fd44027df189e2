#include "twin/model/quadratic_membrane.h"

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>

#include "tests/support/finite_difference.h"
#include "tests/support/random_states.h"
#include "twin/model/material.h"
#include "twin/model/membrane_term.h"
#include "twin/mesh/mesh_refinement.h"

namespace twin::quadratic_membrane_test {
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

// One random triangle refined uniformly: one quadratic patch on six vertices.
SheetMesh random_patch(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  SheetMesh mesh;
  mesh.rest_uv = {Vec2(0, 0) + Vec2(u(rng), u(rng)), Vec2(0.1, 0) + Vec2(u(rng), u(rng)),
                  Vec2(0.04, 0.09) + Vec2(u(rng), u(rng))};
  mesh.triangles = {{0, 1, 2}};
  return refine_uniformly(mesh);
}

VecX element_positions(const QuadraticMembraneElement& e, const VecX& x) {
  VecX xe(18);
  for (int k = 0; k < 6; ++k) xe.segment<3>(3 * k) = x.segment<3>(3 * e.v[k]);
  return xe;
}

// A rectangle of linear triangles refined uniformly.
SheetMesh refined_rectangle(double w, double h, double edge) {
  return refine_uniformly(make_rectangular_sheet(w, h, edge));
}

TEST_CASE("uniform refinement records each coarse triangle's corners and midpoints", "[twin][mesh]") {
  const SheetMesh coarse = make_rectangular_sheet(0.3, 0.2, 0.05);
  const SheetMesh fine = refine_uniformly(coarse);
  REQUIRE(fine.triangle_count() == 4 * coarse.triangle_count());
  REQUIRE(fine.quadratic_patches.size() == coarse.triangles.size());
  CHECK(fine.total_rest_area() == Approx(coarse.total_rest_area()));
  for (std::size_t t = 0; t < coarse.triangles.size(); ++t) {
    const auto& p = fine.quadratic_patches[t];
    for (int k = 0; k < 3; ++k) {
      CHECK(p[k] == coarse.triangles[t][k]);
      const Vec2 mid = 0.5 * (fine.rest_uv[p[k]] + fine.rest_uv[p[(k + 1) % 3]]);
      CHECK((fine.rest_uv[p[3 + k]] - mid).norm() < 1e-12);
    }
  }
  // Any further change of the mesh drops them: they would no longer be its triangles' parents.
  CHECK(refine_near_points(fine, {Vec2(0.1, 0.1)}, {0.02}).quadratic_patches.empty());
}

TEST_CASE("quadratic membrane gradient and Hessian match finite differences", "[twin][energy]") {
  std::mt19937 rng(7);
  const Mat3 c = anisotropic_stiffness();
  for (int trial = 0; trial < 10; ++trial) {
    const SheetMesh mesh = random_patch(rng);
    const QuadraticMembraneElement e = make_quadratic_membrane_element(mesh, 0);
    const VecX x = element_positions(e, testing::random_deformed(mesh.rest_uv, 0.1, 0.2, rng));
    const testing::EnergyFunction f = [&](const VecX& y, VecX* g, Eigen::MatrixXd* h) {
      Vec18 ge;
      Mat18 he;
      const double energy =
          quadratic_membrane_energy(e, c, y, g ? &ge : nullptr, h ? &he : nullptr, HessianMode::kExact);
      if (g) *g = ge;
      if (h) *h = he;
      return energy;
    };
    const auto errors = finite_difference_errors(f, x, 1e-7);
    INFO(errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-6);
  }
}

TEST_CASE("projected quadratic membrane Hessian is positive semi-definite", "[twin][energy]") {
  std::mt19937 rng(11);
  const Mat3 c = anisotropic_stiffness();
  for (int trial = 0; trial < 10; ++trial) {
    const SheetMesh mesh = random_patch(rng);
    const QuadraticMembraneElement e = make_quadratic_membrane_element(mesh, 0);
    // Compressed by 20 % and crumpled: compressive stress everywhere.
    VecX x = element_positions(e, testing::random_deformed(mesh.rest_uv, 0.02, 0.0, rng));
    x *= 0.8;
    Mat18 h;
    quadratic_membrane_energy(e, c, x, nullptr, &h, HessianMode::kProjected);
    const double smallest = Eigen::SelfAdjointEigenSolver<Mat18>(h).eigenvalues().minCoeff();
    CHECK(smallest > -1e-9 * h.norm());
  }
}

TEST_CASE("quadratic membrane passes the patch test: an affine deformation's energy is exact",
          "[twin][energy]") {
  // Under x = A (u, v) + t every element's strain is the exact Green-Lagrange strain of A, so
  // the energy is the rest area times the energy density, as the linear triangles give too.
  const Mat3 c = anisotropic_stiffness();
  const SheetMesh mesh = refined_rectangle(0.4, 0.3, 0.06);
  Eigen::Matrix<double, 3, 2> a;
  a << 1.05, 0.1, -0.03, 0.97, 0.2, 0.05;
  VecX x(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) x.segment<3>(3 * i) = a * mesh.rest_uv[i] + Vec3(0.1, -0.2, 1.0);
  const Vec3 u = a.col(0), v = a.col(1);
  const Vec3 eps(0.5 * (u.squaredNorm() - 1.0), 0.5 * (v.squaredNorm() - 1.0), u.dot(v));
  const double expected_J = mesh.total_rest_area() * 0.5 * eps.dot(c * eps);
  const QuadraticMembraneTerm quadratic(mesh, c);
  const MembraneTerm linear(mesh, c);
  VecX gq = VecX::Zero(x.size()), gl = VecX::Zero(x.size());
  CHECK(quadratic.evaluate(x, &gq, nullptr, HessianMode::kExact) == Approx(expected_J).epsilon(1e-12));
  CHECK(linear.evaluate(x, &gl, nullptr, HessianMode::kExact) == Approx(expected_J).epsilon(1e-12));
  // A rigid motion costs nothing and pulls nowhere.
  const Mat3 rotation = Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  VecX rigid(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    rigid.segment<3>(3 * i) = rotation * Vec3(mesh.rest_uv[i].x(), mesh.rest_uv[i].y(), 0.0) + Vec3(1, 2, 3);
  }
  VecX g = VecX::Zero(rigid.size());
  CHECK(std::abs(quadratic.evaluate(rigid, &g, nullptr, HessianMode::kExact)) < 1e-20);
  CHECK(g.cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("a mesh without quadratic patches is refused by the quadratic membrane", "[twin][energy]") {
  CHECK_THROWS_WITH(QuadraticMembraneTerm(make_rectangular_sheet(0.2, 0.2, 0.05), Mat3::Identity()),
                    Catch::Contains("refined uniformly"));
}

}  // namespace
}  // namespace twin::quadratic_membrane_test
