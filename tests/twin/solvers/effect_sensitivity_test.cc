// Equilibrium sensitivities (equilibrium_sensitivity.h) for the parameters of the bending
// effects: rest curvature K0_uu, K0_vv, K0_uv (1/m) and bending stiffening beta (m^2), at the
// null material (effects absent, where the discrepancy workflow's score test evaluates them) and
// at a material with all of them present.
//  - dg/dp (a forward difference of one scale step, since beta may sit at its bound 0) against a
//    central difference of the energy gradient at fixed x (beta at 0: a secant, the gradient
//    being linear in beta);
//  - adjoint gradients dJ/dp of a marker misfit against re-solved equilibria (central
//    differences; beta at 0: one-sided, second order).
// The rig is that of equilibrium_sensitivity_test.cc: a horizontal sheet sagging between three
// clamps brought 15 % closer together.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "twin/solvers/equilibrium_sensitivity.h"
#include "twin/solvers/static_solver.h"

namespace twin {
namespace {

const std::vector<MaterialParameter> kEffectParameters = {
    MaterialParameter::kRestCurvatureUU, MaterialParameter::kRestCurvatureVV,
    MaterialParameter::kRestCurvatureUV, MaterialParameter::kBendingStiffening};

Material base_material() {
  Material m;
  m.surface_density_kg_m2 = 0.3;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 3000.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 1e-3;
  m.poisson_ratio = 0.3;
  return m;
}

Material effects_material() {
  Material m = base_material();
  m.effects.rest_curvature_uu_1_m = 3.0;
  m.effects.rest_curvature_vv_1_m = -1.5;
  m.effects.rest_curvature_uv_1_m = 1.0;
  m.effects.bending_stiffening_m2 = 0.02;
  return m;
}

NewtonOptions tight_options() {
  NewtonOptions options = default_static_options();
  options.residual_tolerance = 1e-10;
  return options;
}

std::string name(MaterialParameter p) { return std::string(parameter_name(p)); }

struct Rig {
  ShellModel model;
  ClampSet clamps{model.mesh(),
                  {{"a", Vec2(0.04, 0.04), 0.02}, {"b", Vec2(0.37, 0.06), 0.02},
                   {"c", Vec2(0.15, 0.27), 0.02}}};
  SheetPlacement placement{Vec3(-0.2, -0.15, 1.0), Mat3::Identity()};
  std::vector<ClampPose> poses;
  DofMap dofs;
  VecX x;  // the equilibrium

  explicit Rig(const Material& material) : model(make_rectangular_sheet(0.4, 0.3, 0.03), material) {
    Vec2 centre = Vec2::Zero();
    for (int i = 0; i < clamps.size(); ++i) centre += clamps[i].spec().material_point_m / 3.0;
    for (int i = 0; i < clamps.size(); ++i) {
      const Vec2 uv = centre + 0.85 * (clamps[i].spec().material_point_m - centre);
      poses.push_back({placement.to_world(uv), Mat3::Identity(), true});
    }
    dofs = DofMap(clamps.fixed_vertices(model.vertex_count(), poses));
    x = place_flat(model.mesh(), placement);
    const SolveReport report = StaticSolver(model).solve(clamps, poses, x, tight_options());
    INFO(report.brief());
    REQUIRE(report.usable());
    REQUIRE(report.residual < 1e-9);
  }

  // Equilibrium (solved from x) and free energy gradient at x, for p set to `value`.
  VecX resolved(MaterialParameter p, double value) {
    const Material saved = model.material();
    Material changed = saved;
    set_parameter(changed, p, value);
    model.set_material(changed);
    VecX y = x;
    const SolveReport report = StaticSolver(model).solve(clamps, poses, y, tight_options());
    model.set_material(saved);
    INFO(name(p) << " = " << value << ": " << report.brief());
    REQUIRE(report.usable());
    return y;
  }
  VecX gradient_at(MaterialParameter p, double value) {
    const Material saved = model.material();
    Material changed = saved;
    set_parameter(changed, p, value);
    model.set_material(changed);
    VecX g;
    Objective(model.potential_terms()).evaluate(x, &g, nullptr, HessianMode::kExact);
    model.set_material(saved);
    return gather_free(dofs, g);
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

double relative_error(const VecX& value, const VecX& reference) {
  return (value - reference).norm() / reference.norm();
}

TEST_CASE("dg/dp of the bending effects matches differences of the energy gradient",
          "[twin][effects][sensitivity]") {
  for (const Material& material : {base_material(), effects_material()}) {
    Rig rig(material);
    for (MaterialParameter p : kEffectParameters) {
      const double value = get_parameter(material, p);
      const double scale = parameter_scale(p).scale;
      VecX reference;
      if (p == MaterialParameter::kBendingStiffening && value == 0.0) {
        // At the bound: the gradient is linear in beta, so any secant is the derivative.
        reference = (rig.gradient_at(p, 5.0 * scale) - rig.gradient_at(p, 0.0)) / (5.0 * scale);
      } else {
        const double h = 1e-3 * scale;
        reference = (rig.gradient_at(p, value + h) - rig.gradient_at(p, value - h)) / (2.0 * h);
      }
      const VecX dg = gather_free(rig.dofs, force_parameter_derivative(rig.model, rig.dofs, rig.x, p));
      const double error = relative_error(dg, reference);
      INFO(name(p) << " at " << value << ": |dg/dp| " << reference.norm() << ", relative error "
                   << error);
      CHECK(reference.norm() > 0.0);
      CHECK(error < 1e-4);
    }
  }
}

TEST_CASE("adjoint gradients for the bending effects match re-solved equilibria",
          "[twin][effects][sensitivity]") {
  for (const Material& material : {base_material(), effects_material()}) {
    Rig rig(material);
    const MarkerObjective objective(rig);
    EquilibriumSensitivity sensitivity(rig.model, rig.dofs, rig.x);
    const VecX adjoint = sensitivity.adjoint_gradient(objective.gradient(rig.x), kEffectParameters);
    const VecX coordinate =
        sensitivity.coordinate_adjoint_gradient(objective.gradient(rig.x), kEffectParameters);
    for (std::size_t j = 0; j < kEffectParameters.size(); ++j) {
      const MaterialParameter p = kEffectParameters[j];
      const double value = get_parameter(material, p);
      const double scale = parameter_scale(p).scale;
      const double h = 1e-3 * scale;
      double fd;
      if (p == MaterialParameter::kBendingStiffening && value == 0.0) {
        // One-sided, second order: beta cannot go below 0.
        fd = (-3.0 * objective.value(rig.x) + 4.0 * objective.value(rig.resolved(p, h)) -
              objective.value(rig.resolved(p, 2.0 * h))) / (2.0 * h);
      } else {
        fd = (objective.value(rig.resolved(p, value + h)) -
              objective.value(rig.resolved(p, value - h))) / (2.0 * h);
      }
      const double error = std::abs(adjoint(j) - fd) / std::abs(fd);
      INFO(name(p) << " at " << value << ": dJ/dp adjoint " << adjoint(j) << ", re-solved "
                   << fd << ", relative error " << error);
      // Measured: 1e-9 to 2e-4 (beta at 0: the one-sided difference's truncation), 8.5e-4 for
      // K0_uv with beta > 0, where dg/dK0 is no longer exact (the energy is not linear in K0 with
      // stiffening; forward step 1e-4 1/m, dg off by 8e-6) and dJ/dK0_uv is ten times smaller
      // than the other derivatives. A sign error gives 2.
      CHECK(error < 2e-3);
      CHECK(std::abs(-adjoint(j) - fd) / std::abs(fd) > 1.0);
      CHECK(coordinate(j) == Approx(scale * adjoint(j)).epsilon(1e-14));
    }
  }
}

}  // namespace
}  // namespace twin
