// The clamp grip width effect (twin/model/clamp_grip_term.h): derivatives, absence, rigid motions,
// released clamps, and that soft springs out to the width act like jaws that really are wider.
#include <catch2/catch.hpp>
#include <random>

#include "tests/support/random_states.h"
#include "tests/support/term_check.h"
#include "twin/solvers/equilibrium_sensitivity.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace twin::clamp_grip_test {
namespace {

Material strip_material(double grip_width_m) {
  // Width 0 here means the effect absent (strength 0); the model itself keeps a width > 0.
  Material m;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 2000.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 2e-3;
  m.surface_density_kg_m2 = 0.3;
  m.effects.clamp_grip_strength = grip_width_m > 0.0 ? 1.0 : 0.0;
  if (grip_width_m > 0.0) m.effects.clamp_grip_width_m = grip_width_m;
  return m;
}

// A 0.4 m x 0.1 m strip held by one clamp at its left end: a cantilever sagging under gravity.
struct Cantilever {
  explicit Cantilever(double grip_width_m, double grip_radius_m = 0.02)
      : model(make_rectangular_sheet(0.4, 0.1, 0.025), strip_material(grip_width_m)),
        clamps(model.mesh(), {ClampSpec{"A", Vec2(0.02, 0.05), grip_radius_m}}),
        poses(1) {
    model.set_clamp_grips(clamps);
    poses[0].position_m = Vec3(0.02, 0.05, 0.0);
  }
  VecX solve() {
    VecX x = place_flat(model.mesh(), SheetPlacement{});
    StaticSolver statics(model);
    const SolveReport r = statics.solve(clamps, poses, x);
    REQUIRE(r.usable());
    return x;
  }
  // Lowest point of the strip's free end (m, z up).
  double tip_z(const VecX& x) const {
    double z = 0.0;
    for (int v = 0; v < model.vertex_count(); ++v) {
      if (model.mesh().rest_uv[v].x() > 0.399) z = std::min(z, x(3 * v + 2));
    }
    return z;
  }
  ShellModel model;
  ClampSet clamps;
  std::vector<ClampPose> poses;
};

TEST_CASE("clamp grip: gradient and Hessian match finite differences", "[twin][energy][clamp_grip]") {
  Cantilever c(0.05);
  int gripped = 0;
  for (int s = 0; s < c.model.clamp_grip().spring_count(); ++s) gripped += c.model.clamp_grip().spring_stiffness_N_m(s) > 0.0;
  REQUIRE(gripped > 3);
  std::mt19937 rng(11);
  const VecX x = testing::random_deformed(c.model.mesh().rest_uv, 0.2, 0.05, rng);
  const auto errors = testing::term_derivative_errors(c.model.clamp_grip(), x);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-6);
  CHECK(errors.hessian < 1e-6);
}

TEST_CASE("clamp grip: absent at zero strength and for a released clamp, no force under rigid motion",
          "[twin][clamp_grip]") {
  std::mt19937 rng(5);
  Cantilever c(0.0);
  const VecX bent = testing::random_deformed(c.model.mesh().rest_uv, 0.2, 0.05, rng);
  VecX g = VecX::Zero(bent.size());
  CHECK(c.model.clamp_grip().evaluate(bent, &g, nullptr, HessianMode::kExact) == 0.0);
  CHECK(g.norm() == 0.0);

  Cantilever wide(0.08);
  CHECK(wide.model.clamp_grip().evaluate(bent, nullptr, nullptr, HessianMode::kExact) > 0.0);
  std::vector<ClampPose> released(1);
  released[0].engaged = false;
  (void)wide.model.hold_clamps(wide.clamps, released);
  CHECK(wide.model.clamp_grip().evaluate(bent, nullptr, nullptr, HessianMode::kExact) == 0.0);
  (void)wide.model.hold_clamps(wide.clamps, wide.poses);
  CHECK_THROWS_AS(wide.model.hold_clamps(wide.clamps, std::vector<ClampPose>(2)), std::invalid_argument);

  // The springs pull towards the clamp's rigid patch extended: a rigid motion of the flat
  // sheet stretches none of them.
  SheetPlacement turned;
  turned.rotation = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  turned.origin_m = Vec3(0.3, -0.2, 1.1);
  const VecX moved = place_flat(wide.model.mesh(), turned);
  g.setZero();
  CHECK(wide.model.clamp_grip().evaluate(moved, &g, nullptr, HessianMode::kExact) == Approx(0.0).margin(1e-20));
  CHECK(g.norm() < 1e-9);
}

TEST_CASE("clamp grip: springs out to the width hold the strip as wider rigid jaws do", "[twin][clamp_grip]") {
  // The same cantilever held by jaws of radius 2 cm, by jaws of 8 cm (rigid), and by 2 cm jaws
  // with a 6 cm grip width (springs): the width must bring the tip from the first to the second.
  Cantilever narrow(0.0), soft(0.06), rigid(0.0, 0.08);
  const double z_narrow = narrow.tip_z(narrow.solve()), z_soft = soft.tip_z(soft.solve()),
               z_rigid = rigid.tip_z(rigid.solve());
  INFO("tip z (m): narrow " << z_narrow << ", soft grip " << z_soft << ", rigid wide " << z_rigid);
  REQUIRE(z_rigid - z_narrow > 0.01);  // the wider jaws matter here
  // Not exactly: the springs also grip part of the cells the jaws' edge passes through
  // (clamp_grip_term.h), up to one vertex size further out.
  CHECK(z_soft - z_narrow > 0.75 * (z_rigid - z_narrow));
  CHECK(z_soft - z_narrow < 1.35 * (z_rigid - z_narrow));
}

TEST_CASE("clamp grip: the equilibrium's tangents in strength and width match re-solved equilibria",
          "[twin][clamp_grip]") {
  // From the absent effect (strength 0, the score test's point), from a present one, and at the
  // width's upper bound (where a refit's search can stop; the difference must not step out).
  for (const auto& [strength, width_m] :
       {std::pair{0.0, 0.05}, std::pair{0.5, 0.03}, std::pair{0.5, kMaxClampGripWidth_m}}) {
    Cantilever c(0.0);
    Material m = c.model.material();
    m.effects.clamp_grip_strength = strength;
    m.effects.clamp_grip_width_m = width_m;
    c.model.set_material(m);
    const VecX x0 = c.solve();
    const DofMap dofs(c.clamps.fixed_vertices(c.model.vertex_count(), c.poses));
    EquilibriumSensitivity sensitivity(c.model, dofs, x0);
    const std::vector<MaterialParameter> parameters = {MaterialParameter::kClampGripStrength,
                                                       MaterialParameter::kClampGripWidth};
    const Eigen::MatrixXd tangents = sensitivity.tangents(parameters);
    for (int j = 0; j < 2; ++j) {
      if (strength == 0.0 && j == 1) {
        CHECK(tangents.col(1).norm() == 0.0);  // the width does nothing without strength
        continue;
      }
      // At the bound only the width is in question (its difference must stay in range); there
      // the strength's re-solved reference is no more accurate than a few per cent.
      if (width_m == kMaxClampGripWidth_m && j == 0) continue;
      const double h = j == 0 ? 1e-6 : (width_m < kMaxClampGripWidth_m ? 1e-6 : -1e-6) * width_m;
      Material stepped = m;
      set_parameter(stepped, parameters[j], get_parameter(m, parameters[j]) + h);
      c.model.set_material(stepped);
      VecX x1 = x0;
      StaticSolver statics(c.model);
      REQUIRE(statics.solve(c.clamps, c.poses, x1).usable());
      c.model.set_material(m);
      const VecX difference = (x1 - x0) / h;
      INFO("strength " << strength << ", width " << width_m << " m, " << parameter_name(parameters[j])
                       << ": |tangent| " << tangents.col(j).norm() << ", |difference| " << difference.norm());
      REQUIRE(difference.norm() > 1e-3);
      CHECK((tangents.col(j) - difference).norm() < 0.02 * difference.norm());
    }
  }
}

}  // namespace
}  // namespace twin::clamp_grip_test
