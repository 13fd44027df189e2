// Plate bending (plate_bending.h): derivatives against finite differences, and the curvature and
// energy of each triangle against the continuum plate for constant curvatures of every kind
// (cylinders along several directions, a sphere, a saddle, a pure twist) on both triangulations.
#include "twin/model/plate_bending_term.h"

#include <catch2/catch.hpp>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "tests/support/random_states.h"
#include "tests/support/term_check.h"
#include "twin/model/bending_calibration.h"

namespace twin {
namespace {

// An orthotropic laminate: stiff along u, soft twist, a Poisson coupling.
const Mat3 kRigidity = plate_rigidity_matrix(2e-3, 8e-4, 3e-4, 2e-4);

// The rest mesh lifted onto w = 1/2 (u, v) K (u, v)^T about its centre (small K: the sheet
// stretches to second order, the angles are those of the curvature to first order).
VecX lifted(const SheetMesh& mesh, const Vec3& k_uu_vv_uv) {
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : mesh.rest_uv) centre += p;
  centre /= mesh.vertex_count();
  VecX x(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const Vec2 d = mesh.rest_uv[i] - centre;
    const double w = 0.5 * k_uu_vv_uv(0) * d.x() * d.x() + 0.5 * k_uu_vv_uv(1) * d.y() * d.y() +
                     k_uu_vv_uv(2) * d.x() * d.y();
    x.segment<3>(3 * i) = Vec3(mesh.rest_uv[i].x(), mesh.rest_uv[i].y(), w);
  }
  return x;
}

double continuum_density(const Vec3& k_uu_vv_uv) {
  const Vec3 kappa(k_uu_vv_uv(0), k_uu_vv_uv(1), 2.0 * k_uu_vv_uv(2));
  return 0.5 * kappa.dot(kRigidity * kappa);
}

TEST_CASE("plate bending derivatives match finite differences", "[twin][energy]") {
  std::mt19937 rng(13);
  for (const auto pattern : {TriangulationPattern::kOffsetRows, TriangulationPattern::kRightTriangles}) {
    const SheetMesh mesh = make_rectangular_sheet(0.12, 0.1, 0.04, pattern);
    for (int trial = 0; trial < 6; ++trial) {
      PlateBendingTerm term(mesh, kRigidity);
      if (trial % 2) term.set_rest_curvature({3.0, -1.0, 2.0});
      if (trial % 3 == 2) term.set_stiffening(0.05);
      const VecX x = testing::random_deformed(mesh.rest_uv, 0.1, 0.2, rng);
      const auto errors = testing::term_derivative_errors(term, x, 1e-7);
      INFO("trial " << trial << ": " << errors.report());
      CHECK(errors.gradient < 1e-6);
      CHECK(errors.hessian < 1e-6);
    }
  }
}

TEST_CASE("plate bending's projected Hessian is positive semi-definite", "[twin][energy]") {
  std::mt19937 rng(17);
  const SheetMesh mesh = make_rectangular_sheet(0.12, 0.1, 0.04);
  PlateBendingTerm term(mesh, kRigidity);
  term.set_rest_curvature({3.0, -1.0, 2.0});
  term.set_stiffening(0.5);
  const VecX x = testing::random_deformed(mesh.rest_uv, 0.1, 0.3, rng);
  const Objective objective({&term});
  const DofMap dofs(std::vector<char>(mesh.vertex_count(), 0));
  HessianPattern pattern(dofs, objective.stencils());
  objective.evaluate(x, nullptr, &pattern, HessianMode::kProjected);
  const Eigen::MatrixXd upper(pattern.matrix());
  const Eigen::MatrixXd h = upper.selfadjointView<Eigen::Upper>();
  const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues().minCoeff();
  CHECK(smallest > -1e-10 * h.norm());
}

TEST_CASE("each interior triangle reads a constant curvature exactly and stores the continuum energy",
          "[twin][energy]") {
  const double c = 0.05;  // 1/m
  const double a30 = M_PI / 6, a45 = M_PI / 4, a135 = 3 * M_PI / 4;
  auto cylinder = [c](double angle) {
    return Vec3(c * std::cos(angle) * std::cos(angle), c * std::sin(angle) * std::sin(angle),
                c * std::cos(angle) * std::sin(angle));
  };
  const std::vector<std::pair<std::string, Vec3>> shapes = {
      {"cylinder along u", cylinder(0.0)}, {"cylinder at 30 deg", cylinder(a30)},
      {"cylinder at 45 deg", cylinder(a45)}, {"cylinder along v", cylinder(M_PI / 2)},
      {"cylinder at 135 deg", cylinder(a135)}, {"sphere", Vec3(c, c, 0.0)},
      {"saddle", Vec3(c, -c, 0.0)}, {"pure twist", Vec3(0.0, 0.0, c)}};
  for (const auto pattern : {TriangulationPattern::kOffsetRows, TriangulationPattern::kRightTriangles}) {
    const SheetMesh mesh = make_rectangular_sheet(0.3, 0.24, 0.03, pattern);
    const PlateBendingTerm term(mesh, kRigidity);
    for (const auto& [name, k] : shapes) {
      INFO((pattern == TriangulationPattern::kOffsetRows ? "offset rows, " : "right triangles, ") << name);
      const VecX x = lifted(mesh, k);
      double worst = 0.0, area = 0.0;
      for (int e = 0; e < term.element_count(); ++e) {
        if (term.hinge_count(e) < 3) continue;
        worst = std::max(worst, (term.curvature(x, e) - k).norm() / k.norm());
        area += term.rest_area(e);
      }
      CHECK(worst < 5e-3);
      // The whole sheet: interior triangles store the continuum's energy, those on the free
      // edges at most theirs.
      const double energy = term.evaluate(x, nullptr, nullptr, HessianMode::kExact);
      const double interior = continuum_density(k) * area;
      const double all = continuum_density(k) * mesh.total_rest_area();
      CHECK(energy > 0.99 * interior);
      CHECK(energy < 1.01 * all);
    }
  }
}

TEST_CASE("a cylinder costs D(direction)/2 kappa^2 per area, the direction's plate rigidity",
          "[twin][energy]") {
  // Wrapped without stretching (wrap_on_cylinder), finite curvature: the energy of interior
  // triangles per area against the continuum.
  const SheetMesh mesh = make_rectangular_sheet(0.3, 0.24, 0.02);
  const PlateBendingTerm term(mesh, kRigidity);
  for (double angle : {0.0, M_PI / 6, M_PI / 4, M_PI / 2, 2.0}) {
    const double kappa = 2.0;
    const VecX x = wrap_on_cylinder(mesh, angle, kappa);
    const Vec3 k(kappa * std::cos(angle) * std::cos(angle), kappa * std::sin(angle) * std::sin(angle),
                 kappa * std::cos(angle) * std::sin(angle));
    double worst = 0.0;
    for (int e = 0; e < term.element_count(); ++e) {
      if (term.hinge_count(e) == 3) worst = std::max(worst, (term.curvature(x, e) - k).norm() / kappa);
    }
    INFO("angle " << angle << " rad");
    CHECK(worst < 2e-3);
  }
}

TEST_CASE("a sheet curved at rest stores nothing in its rest shape, stiffening is isotropic",
          "[twin][energy]") {
  const SheetMesh mesh = make_rectangular_sheet(0.3, 0.24, 0.02);
  PlateBendingTerm term(mesh, kRigidity);
  const double kappa = 1.5;
  term.set_rest_curvature({kappa, 0.0, 0.0});
  const VecX wrapped = wrap_on_cylinder(mesh, 0.0, kappa);
  VecX flat(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) flat.segment<3>(3 * i) = Vec3(mesh.rest_uv[i].x(), mesh.rest_uv[i].y(), 0.0);
  const double e_rest = term.evaluate(wrapped, nullptr, nullptr, HessianMode::kExact);
  const double e_flat = term.evaluate(flat, nullptr, nullptr, HessianMode::kExact);
  CHECK(e_rest < 1e-4 * e_flat);

  // Stiffening beta: E(beta) / E(0) - 1 = beta kappa^2 / 2 for every direction of the cylinder.
  term.set_rest_curvature({});
  const double beta = 0.02;
  for (double angle : {0.0, M_PI / 6, M_PI / 4, M_PI / 3, M_PI / 2}) {
    const VecX x = wrap_on_cylinder(mesh, angle, kappa);
    term.set_stiffening(0.0);
    const double e0 = term.evaluate(x, nullptr, nullptr, HessianMode::kExact);
    term.set_stiffening(beta);
    const double e1 = term.evaluate(x, nullptr, nullptr, HessianMode::kExact);
    INFO("angle " << angle);
    CHECK(e1 / e0 - 1.0 == Approx(0.5 * beta * kappa * kappa).epsilon(0.03));
  }
}

// A triangle and its three neighbours as they came out of the jaw refinement of a lab trial's
// twin (composite, 1500 triangles, quadratic membrane): the hinges across two of its edges
// respond to curvature in exact proportion, so no curvature tensor is determined by their
// angles apart. The element used to throw ("do not determine a curvature") or, depending on
// the rigidity's rounding, to invert a singular matrix.
SheetMesh proportional_hinges_patch() {
  SheetMesh mesh;
  mesh.rest_uv = {{1.1047098214285713, 0.15468749999999998}, {1.1020982142857141, 0.15937499999999999},
                  {1.0864285714285713, 0.14999999999999999}, {1.0968749999999998, 0.16875000000000001},
                  {1.1073214285714283, 0.14999999999999999}, {1.1203794642857141, 0.1640625}};
  mesh.triangles = {{0, 1, 2}, {2, 1, 3}, {0, 2, 4}, {1, 0, 5}};
  return mesh;
}

TEST_CASE("a triangle whose hinges do not determine a curvature bends with the pseudo-inverse",
          "[twin][energy]") {
  const SheetMesh mesh = proportional_hinges_patch();
  for (const double bending_Nm : {8e-4, 1e-3, 3.7e-4}) {
    INFO("D " << bending_Nm << " N*m");
    const Mat3 d = plate_rigidity_matrix(bending_Nm, bending_Nm, 0.3 * bending_Nm, 0.35 * bending_Nm);
    PlateBendingTerm term(mesh, d);
    REQUIRE(term.hinge_count(0) == 3);
    // A cylinder: finite energy, no more than the continuum's over the whole patch (the
    // undetermined combination of angles carries none).
    const double c = 2.0;  // 1/m
    for (const double angle : {0.0, 0.7, M_PI / 2}) {
      const Vec3 k(c * std::cos(angle) * std::cos(angle), c * std::sin(angle) * std::sin(angle),
                   c * std::cos(angle) * std::sin(angle));
      const VecX x = lifted(mesh, k);
      const double energy = term.evaluate(x, nullptr, nullptr, HessianMode::kExact);
      const Vec3 kappa(k(0), k(1), 2.0 * k(2));
      const double continuum = 0.5 * kappa.dot(d * kappa) * mesh.total_rest_area();
      CHECK(std::isfinite(energy));
      CHECK(energy > 0.0);
      CHECK(energy < 1.5 * continuum);
      CHECK(term.curvature(x, 0).allFinite());
    }
    std::mt19937 rng(5);
    const VecX x = testing::random_deformed(mesh.rest_uv, 0.002, 0.2, rng);
    const auto errors = testing::term_derivative_errors(term, x, 1e-8);
    INFO(errors.report());
    CHECK(errors.gradient < 1e-5);
    CHECK(errors.hessian < 1e-5);
  }
}

TEST_CASE("plate bending refuses a rigidity that is not positive definite", "[twin][energy]") {
  const SheetMesh mesh = make_rectangular_sheet(0.1, 0.1, 0.03);
  CHECK_THROWS_WITH(PlateBendingTerm(mesh, plate_rigidity_matrix(1e-3, 1e-3, 2e-3, 1e-4)),
                    Catch::Contains("D12^2 < D11 D22"));
  CHECK_THROWS_WITH(PlateBendingTerm(mesh, plate_rigidity_matrix(1e-3, 1e-3, 0.0, 0.0)),
                    Catch::Contains("D66"));
}

}  // namespace
}  // namespace twin
