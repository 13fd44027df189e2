// Derivatives of a static equilibrium with respect to material parameters, checked against the
// thing they predict: equilibria re-solved at perturbed materials.
//
// The sheet (0.4 x 0.3 m, ~350 triangles) lies horizontally and is held by three clamps at
// different distances from its corners, brought 15 % closer to their centroid so that it sags
// and bending, tension, shear and weight all shape it. Finite differences re-solve the
// equilibrium at p (1 +- h) from the equilibrium x to a residual of ~1e-10; with h = 1e-3 their
// truncation error is ~h^2 (measured 1e-7 to 3e-6 relative for dx/dp, up to 8e-6 for dJ/dp; 3e-8
// or better at h = 1e-4, the solver's tolerance floor), so a tolerance of 1e-4 leaves a margin
// of 13 or more, while the planted bugs below (a sign, the wrong Hessian) give errors of 0.5 to 2.

#include "twin/solvers/equilibrium_sensitivity.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>

#include "twin/solvers/static_solver.h"

namespace twin::equilibrium_sensitivity_test {
namespace {

constexpr double kFiniteDifferenceStep = 1e-3;  // relative, in p
constexpr double kTolerance = 1e-4;             // relative agreement with finite differences

const std::vector<MaterialParameter> kParameters = {
    MaterialParameter::kTensile, MaterialParameter::kTensileU, MaterialParameter::kShear,
    MaterialParameter::kBending, MaterialParameter::kBendingV, MaterialParameter::kSurfaceDensity};

Material test_material() {
  Material m;
  m.name = "sensitivity test";
  m.surface_density_kg_m2 = 0.3;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 3000.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 1e-3;
  m.poisson_ratio = 0.3;
  return m;
}

NewtonOptions tight_options() {
  NewtonOptions options = default_static_options();
  options.residual_tolerance = 1e-10;
  return options;
}

std::string name(MaterialParameter p) { return std::string(parameter_name(p)); }

double relative_error(const VecX& value, const VecX& reference) {
  return (value - reference).norm() / reference.norm();
}

struct Rig {
  ShellModel model{make_rectangular_sheet(0.4, 0.3, 0.03), test_material()};
  ClampSet clamps{model.mesh(),
                  {{"a", Vec2(0.04, 0.04), 0.02}, {"b", Vec2(0.37, 0.06), 0.02},
                   {"c", Vec2(0.15, 0.27), 0.02}}};
  SheetPlacement placement{Vec3(-0.2, -0.15, 1.0), Mat3::Identity()};
  std::vector<ClampPose> poses;
  DofMap dofs;
  VecX x;  // the equilibrium

  Rig() {
    Vec2 centre = Vec2::Zero();
    for (int i = 0; i < clamps.size(); ++i) {
      centre += clamps[i].spec().material_point_m / clamps.size();
    }
    for (int i = 0; i < clamps.size(); ++i) {
      const Vec2 uv = centre + 0.85 * (clamps[i].spec().material_point_m - centre);
      poses.push_back({placement.to_world(uv), Mat3::Identity(), true});
    }
    dofs = DofMap(clamps.fixed_vertices(model.vertex_count(), poses));
    x = place_flat(model.mesh(), placement);
    StaticSolver solver(model);
    const SolveReport report = solver.solve(clamps, poses, x, tight_options());
    INFO(report.brief());
    REQUIRE(report.usable());
    REQUIRE(report.residual < 1e-9);
  }

  // The equilibrium for the material with parameter p scaled by `factor`, solved from x.
  VecX resolved(MaterialParameter p, double factor) {
    const Material saved = model.material();
    Material changed = saved;
    scale_parameter(changed, p, factor);
    model.set_material(changed);
    VecX y = x;
    StaticSolver solver(model);
    const SolveReport report = solver.solve(clamps, poses, y, tight_options());
    model.set_material(saved);
    INFO(name(p) << " x " << factor << ": " << report.brief());
    REQUIRE(report.usable());
    return y;
  }

  // Central difference of the equilibrium in p: dx/dp (m per unit of p).
  VecX finite_difference_tangent(MaterialParameter p) {
    const double value = get_parameter(model.material(), p);
    const double h = kFiniteDifferenceStep;
    return (resolved(p, 1.0 + h) - resolved(p, 1.0 - h)) / (2.0 * h * value);
  }
};

// J(x) = sum over a few free vertices of |x_v - target_v|^2 (m^2), targets off the equilibrium.
struct MarkerObjective {
  std::vector<int> vertices;
  std::vector<Vec3> targets_m;

  explicit MarkerObjective(const Rig& rig) {
    const int n = rig.model.vertex_count();
    const Vec3 offsets[] = {Vec3(0.01, -0.02, 0.005), Vec3(-0.015, 0.0, -0.01),
                            Vec3(0.0, 0.012, 0.02), Vec3(0.007, 0.007, -0.007)};
    for (int k = 0, v = n / 7; k < 4; ++k, v = (v + n / 4) % n) {
      while (rig.dofs.is_fixed(v)) v = (v + 1) % n;
      vertices.push_back(v);
      targets_m.push_back(vertex(rig.x, v) + offsets[k]);
    }
  }
  double value(const VecX& x) const {
    double j = 0.0;
    for (std::size_t k = 0; k < vertices.size(); ++k) {
      j += (vertex(x, vertices[k]) - targets_m[k]).squaredNorm();
    }
    return j;
  }
  VecX gradient(const VecX& x) const {
    VecX g = VecX::Zero(x.size());
    for (std::size_t k = 0; k < vertices.size(); ++k) {
      vertex(g, vertices[k]) = 2.0 * (vertex(x, vertices[k]) - targets_m[k]);
    }
    return g;
  }
};

TEST_CASE("equilibrium tangents dx/dp match re-solved equilibria", "[twin][sensitivity]") {
  Rig rig;
  EquilibriumSensitivity sensitivity(rig.model, rig.dofs, rig.x);
  CHECK(sensitivity.residual() < 1e-9);
  CHECK(sensitivity.relative_smallest_eigenvalue() > 1e-8);  // measured 2.6e-6: well conditioned

  const Eigen::MatrixXd tangents = sensitivity.tangents(kParameters);
  const Eigen::MatrixXd coordinate_tangents = sensitivity.coordinate_tangents(kParameters);
  REQUIRE(tangents.rows() == rig.x.size());
  REQUIRE(tangents.cols() == static_cast<Eigen::Index>(kParameters.size()));

  // A planted bug: the projected (positive semi-definite) Hessian the Newton solver uses far
  // from equilibrium, in place of the exact one. It drops compressive membrane stress and the
  // curvature of the hinge angles, which the sagging sheet has.
  const Objective objective(rig.model.potential_terms());
  HessianPattern projected(rig.dofs, objective.stencils());
  objective.evaluate(rig.x, nullptr, &projected, HessianMode::kProjected);
  SparseCholesky projected_cholesky;
  projected_cholesky.analyze(projected.matrix());
  REQUIRE(projected_cholesky.factorize(projected.matrix()));

  for (std::size_t j = 0; j < kParameters.size(); ++j) {
    const MaterialParameter p = kParameters[j];
    const double value = get_parameter(rig.model.material(), p);
    const VecX fd = rig.finite_difference_tangent(p);
    const VecX tangent = tangents.col(j);
    const double error = relative_error(tangent, fd);
    INFO(name(p) << ": |dx/d log p| = " << value * fd.norm() << " m, relative error " << error);
    CHECK(error < kTolerance);
    CHECK(relative_error(coordinate_tangents.col(j), value * tangent) <= 1e-14);
    for (int v = 0; v < rig.model.vertex_count(); ++v) {
      if (rig.dofs.is_fixed(v)) CHECK(vertex(tangent, v).isZero(0.0));
    }

    // Planted bugs must fail the same comparison.
    const VecX dg = sensitivity.force_derivative(p);
    const VecX sign_flipped = sensitivity.solve(dg);  // dx/dp = +K^-1 dg/dp
    CHECK(relative_error(sign_flipped, fd) > 1.0);
    const VecX wrong_hessian = -projected_cholesky.solve(gather_free(rig.dofs, dg));
    CHECK(relative_error(wrong_hessian, gather_free(rig.dofs, fd)) > 0.1);  // measured 0.5-0.9
  }
}

TEST_CASE("adjoint gradients dJ/dp match re-solved equilibria and forward tangents",
          "[twin][sensitivity]") {
  Rig rig;
  const MarkerObjective objective(rig);
  EquilibriumSensitivity sensitivity(rig.model, rig.dofs, rig.x);
  const VecX dJ_dx = objective.gradient(rig.x);
  const VecX adjoint = sensitivity.adjoint_gradient(dJ_dx, kParameters);
  const VecX log_adjoint = sensitivity.coordinate_adjoint_gradient(dJ_dx, kParameters);
  const Eigen::MatrixXd tangents = sensitivity.tangents(kParameters);
  REQUIRE(adjoint.size() == static_cast<Eigen::Index>(kParameters.size()));

  for (std::size_t j = 0; j < kParameters.size(); ++j) {
    const MaterialParameter p = kParameters[j];
    const double value = get_parameter(rig.model.material(), p);
    const double h = kFiniteDifferenceStep;
    const double fd = (objective.value(rig.resolved(p, 1.0 + h)) -
                       objective.value(rig.resolved(p, 1.0 - h))) / (2.0 * h * value);
    const double forward = dJ_dx.dot(tangents.col(j));
    const double adjoint_error = std::abs(adjoint(j) - fd) / std::abs(fd);
    // The same linear algebra taken in the other order: equal up to rounding.
    const double forward_adjoint_difference = std::abs(adjoint(j) - forward) / std::abs(forward);
    INFO(name(p) << ": dJ/d log p = " << value * fd << " m^2; relative error of the adjoint "
                 << adjoint_error << ", adjoint vs forward " << forward_adjoint_difference);
    CHECK(adjoint_error < kTolerance);
    CHECK(forward_adjoint_difference < 1e-10);
    CHECK(std::abs(log_adjoint(j) - value * adjoint(j)) <= 1e-14 * std::abs(log_adjoint(j)));
    // Planted bug: dJ/dp = +lambda^T dg/dp.
    const double flipped = sensitivity.solve(dJ_dx).dot(sensitivity.force_derivative(p));
    CHECK(std::abs(flipped - fd) / std::abs(fd) > 1.0);
  }
}

TEST_CASE("dg/dp is exact up to rounding where the energy is linear in the parameter",
          "[twin][sensitivity]") {
  Rig rig;
  const Objective objective(rig.model.potential_terms());
  auto gradient_at = [&](MaterialParameter p, double factor) {
    const Material saved = rig.model.material();
    Material changed = saved;
    scale_parameter(changed, p, factor);
    rig.model.set_material(changed);
    VecX g;
    objective.evaluate(rig.x, &g, nullptr, HessianMode::kExact);
    rig.model.set_material(saved);
    return gather_free(rig.dofs, g);
  };
  for (MaterialParameter p : {MaterialParameter::kTensile, MaterialParameter::kShear,
                              MaterialParameter::kBending, MaterialParameter::kBendingV,
                              MaterialParameter::kSurfaceDensity}) {
    // Linear: the derivative equals the secant over a 50 % change.
    const double value = get_parameter(rig.model.material(), p);
    const VecX secant = (gradient_at(p, 1.5) - gradient_at(p, 1.0)) / (0.5 * value);
    const VecX dg =
        gather_free(rig.dofs, force_parameter_derivative(rig.model, rig.dofs, rig.x, p));
    const double error = relative_error(dg, secant);
    INFO(name(p) << ": relative difference from the secant " << error);
    CHECK(error < 1e-10);  // measured 1e-12
  }
  // Y_u alone enters C through 1 / (1 - nu^2 Y_v / Y_u): not linear, so the secant differs, and
  // the central difference has an O(h^2) error: steps 1e-4 and 1e-5 agree to ~1e-9.
  const MaterialParameter p = MaterialParameter::kTensileU;
  const double value = get_parameter(rig.model.material(), p);
  const VecX secant = (gradient_at(p, 1.5) - gradient_at(p, 1.0)) / (0.5 * value);
  const VecX dg = force_parameter_derivative(rig.model, rig.dofs, rig.x, p);
  const VecX dg_fine = force_parameter_derivative(rig.model, rig.dofs, rig.x, p, 1e-5);
  const double nonlinearity = relative_error(gather_free(rig.dofs, dg), secant);
  const double truncation = relative_error(dg, dg_fine);
  INFO("Y_u: secant differs by " << nonlinearity << ", steps 1e-4 and 1e-5 by " << truncation);
  CHECK(nonlinearity > 1e-3);
  CHECK(truncation < 1e-8);  // measured 8e-10
}

TEST_CASE("the model's material is restored after sensitivities, also on an exception",
          "[twin][sensitivity]") {
  Rig rig;
  const Material before = rig.model.material();
  const Objective objective(rig.model.potential_terms());
  VecX g_before, g_after;
  objective.evaluate(rig.x, &g_before, nullptr, HessianMode::kExact);
  {
    EquilibriumSensitivity sensitivity(rig.model, rig.dofs, rig.x);
    sensitivity.tangents(kParameters);
    sensitivity.adjoint_gradient(MarkerObjective(rig).gradient(rig.x), kParameters);
  }
  for (MaterialParameter p : kAllMaterialParameters) {
    CHECK(get_parameter(rig.model.material(), p) == get_parameter(before, p));
  }
  CHECK(rig.model.material().poisson_ratio == before.poisson_ratio);
  objective.evaluate(rig.x, &g_after, nullptr, HessianMode::kExact);
  REQUIRE(g_after.size() == g_before.size());
  CHECK(std::memcmp(g_after.data(), g_before.data(), sizeof(double) * g_before.size()) == 0);

  // A material at the edge of stability, nu^2 Y_v / Y_u = 1 - 5e-5: Y_u (1 + h) is accepted,
  // Y_u (1 - h) is not, after the model has been changed once.
  Material edge = test_material();
  edge.poisson_ratio = std::sqrt(1.0 - 5e-5);
  ShellModel model(make_rectangular_sheet(0.4, 0.3, 0.05), edge);
  const DofMap dofs(std::vector<char>(model.vertex_count(), 0));
  const VecX flat = place_flat(model.mesh(), SheetPlacement{});
  CHECK_THROWS_AS(force_parameter_derivative(model, dofs, flat, MaterialParameter::kTensileU),
                  std::invalid_argument);
  CHECK(model.material().tensile_stiffness_u_N_m == edge.tensile_stiffness_u_N_m);
  CHECK(model.material().poisson_ratio == edge.poisson_ratio);
  VecX g_model, g_fresh;
  Objective(model.potential_terms()).evaluate(flat + VecX::Constant(flat.size(), 1e-3), &g_model,
                                              nullptr, HessianMode::kExact);
  ShellModel fresh(make_rectangular_sheet(0.4, 0.3, 0.05), edge);
  Objective(fresh.potential_terms()).evaluate(flat + VecX::Constant(flat.size(), 1e-3), &g_fresh,
                                              nullptr, HessianMode::kExact);
  CHECK(std::memcmp(g_model.data(), g_fresh.data(), sizeof(double) * g_fresh.size()) == 0);
}

void check_not_positive_definite(ShellModel& model, const DofMap& dofs, const VecX& x) {
  try {
    EquilibriumSensitivity sensitivity(model, dofs, x);
    FAIL("expected NotPositiveDefiniteError; smallest eigenvalue estimate "
         << sensitivity.relative_smallest_eigenvalue());
  } catch (const NotPositiveDefiniteError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find("not positive definite") != std::string::npos);
    CHECK(std::string(e.what()).find(std::to_string(dofs.free_dof_count()) + " free DOFs") !=
          std::string::npos);
  }
}

TEST_CASE("a system that does not hold the sheet is reported as not positive definite",
          "[twin][sensitivity]") {
  Rig rig;
  const int n = rig.model.vertex_count();
  SECTION("the hanging sheet's shape with the clamps let go") {
    check_not_positive_definite(rig.model, DofMap(std::vector<char>(n, 0)), rig.x);
  }
  SECTION("a flat sheet held along one straight edge, free to swing about it") {
    // K is singular here (rotation about the edge costs nothing); rounding lets the Cholesky
    // factorisation through on this mesh, and the eigenvalue bound catches it.
    ShellModel model(make_rectangular_sheet(0.4, 0.3, 0.05), test_material());
    std::vector<char> edge(model.vertex_count(), 0);
    for (int i = 0; i < model.vertex_count(); ++i) edge[i] = model.mesh().rest_uv[i].x() == 0.0;
    check_not_positive_definite(model, DofMap(edge), place_flat(model.mesh(), SheetPlacement{}));
  }
  SECTION("a flat sheet compressed 5 % between two held edges (buckling)") {
    VecX x = place_flat(rig.model.mesh(), rig.placement);
    std::vector<char> edges(n, 0);
    for (int i = 0; i < n; ++i) {
      const double u = rig.model.mesh().rest_uv[i].x();
      edges[i] = u == 0.0 || u == 0.4;
      x(3 * i) = rig.placement.origin_m.x() + 0.95 * u;
    }
    check_not_positive_definite(rig.model, DofMap(edges), x);
  }
  SECTION("sizes that do not match the model, or nothing free to move") {
    CHECK_THROWS_AS(EquilibriumSensitivity(rig.model, rig.dofs, rig.x.head(3 * n - 3)),
                    std::invalid_argument);
    CHECK_THROWS_AS(EquilibriumSensitivity(rig.model, DofMap(std::vector<char>(n - 1, 0)), rig.x),
                    std::invalid_argument);
    CHECK_THROWS_AS(EquilibriumSensitivity(rig.model, DofMap(std::vector<char>(n, 1)), rig.x),
                    std::invalid_argument);
  }
}

TEST_CASE("update refactorises at a new material's equilibrium, a stale factor is refused",
          "[twin][sensitivity]") {
  Rig rig;
  EquilibriumSensitivity sensitivity(rig.model, rig.dofs, rig.x);
  Material stiffer = rig.model.material();
  stiffer.bending_rigidity_u_Nm = stiffer.bending_rigidity_v_Nm = 3e-3;
  rig.model.set_material(stiffer);
  CHECK_THROWS_AS(sensitivity.tangents(kParameters), std::logic_error);

  VecX x = rig.x;
  StaticSolver solver(rig.model);
  REQUIRE(solver.solve(rig.clamps, rig.poses, x, tight_options()).usable());
  sensitivity.update(x);
  EquilibriumSensitivity fresh(rig.model, rig.dofs, x);
  const Eigen::MatrixXd updated = sensitivity.coordinate_tangents(kParameters);
  const Eigen::MatrixXd reference = fresh.coordinate_tangents(kParameters);
  CHECK((updated - reference).norm() <= 1e-12 * reference.norm());
}

}  // namespace
}  // namespace twin::equilibrium_sensitivity_test
