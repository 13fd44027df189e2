// The clamp slip effect (twin/model/clamp_slip_term.h): derivatives, absence, released clamps, that a
// clamp gives way by its compliance times the pull along its jaws, and the equilibrium's
// tangent in the compliance (the score test's column) against re-solved equilibria.
#include <catch2/catch.hpp>
#include <random>

#include "tests/support/random_states.h"
#include "tests/support/term_check.h"
#include "twin/solvers/equilibrium_sensitivity.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace twin::clamp_slip_test {
namespace {

Material strip_material(double compliance_m_N) {
  Material m;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 2000.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 2e-3;
  m.surface_density_kg_m2 = 0.3;
  m.effects.clamp_slip_compliance_m_N = compliance_m_N;
  return m;
}

// A 0.1 m x 0.4 m strip (u across, v along) held by one clamp of radius 2 cm at the middle of
// one short end. `turn` places the sheet: the clamp's pose turns the material frame with it.
struct HeldStrip {
  HeldStrip(double compliance_m_N, const Mat3& turn, bool slips = true)
      : model(make_rectangular_sheet(0.1, 0.4, 0.025), strip_material(compliance_m_N)),
        clamps(model.mesh(), {ClampSpec{"A", Vec2(0.05, 0.01), 0.02}}),
        poses(1) {
    if (slips) model.set_clamp_slips(clamps);
    placement.rotation = turn;
    placement.origin_m = Vec3(0.0, 0.0, 1.0);
    poses[0].position_m = placement.to_world(Vec2(0.05, 0.01));
    poses[0].rotation = turn;
  }
  VecX solve() {
    VecX x = place_flat(model.mesh(), placement);
    StaticSolver statics(model);
    const SolveReport r = statics.solve(clamps, poses, x);
    REQUIRE(r.usable());
    return x;
  }
  ShellModel model;
  ClampSet clamps;
  SheetPlacement placement;
  std::vector<ClampPose> poses;
};

// u along world x, v straight down, the sheet's normal along world y: a strip hanging from its
// clamp, its whole weight pulling along the jaws.
Mat3 hanging() {
  Mat3 r;
  r.col(0) = Vec3(1.0, 0.0, 0.0);
  r.col(1) = Vec3(0.0, 0.0, -1.0);
  r.col(2) = Vec3(0.0, 1.0, 0.0);
  return r;
}

// The strip sticking out sideways and 30 degrees down: the weight pulls partly along the jaws
// and partly across them, and the strip bends.
Mat3 inclined() {
  return Eigen::AngleAxisd(-0.5236, Vec3::UnitX()).toRotationMatrix();
}

}  // namespace

TEST_CASE("clamp slip: gradient and Hessian match finite differences", "[twin][energy][clamp_slip]") {
  HeldStrip s(0.01, inclined());
  REQUIRE(s.model.clamp_slip().spring_count() >= 3);
  (void)s.model.hold_clamps(s.clamps, s.poses);
  std::mt19937 rng(13);
  const VecX x = testing::random_deformed(s.model.mesh().rest_uv, 0.2, 0.05, rng);
  for (const EnergyTerm* part : {static_cast<const EnergyTerm*>(&s.model.clamp_slip()), &s.model.clamp_slip().coupling()}) {
    const auto errors = testing::term_derivative_errors(*part, x);
    INFO(part->name() << ": " << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-6);
  }
}

TEST_CASE("clamp slip: frees the clamped vertices, holds them where rigid jaws would at zero compliance",
          "[twin][clamp_slip]") {
  HeldStrip rigid(0.0, inclined(), false), absent(0.0, inclined());
  const DofMap fixed = rigid.model.hold_clamps(rigid.clamps, rigid.poses);
  const DofMap freed = absent.model.hold_clamps(absent.clamps, absent.poses);
  CHECK(fixed.free_vertex_count() == rigid.model.vertex_count() - static_cast<int>(rigid.clamps[0].vertices().size()));
  CHECK(freed.free_vertex_count() == absent.model.vertex_count());
  CHECK_THROWS_AS(absent.model.hold_clamps(absent.clamps, std::vector<ClampPose>(2)), std::invalid_argument);

  const VecX x_rigid = rigid.solve(), x_absent = absent.solve();
  // The strip weighs 0.12 N, and rigid jaws give 0.1 micrometre per newton. The patch's
  // vertices carry the strip's bending moment as a couple of larger forces, and the patch's
  // turn is magnified 20x at the tip 0.4 m away: under a micrometre, against millimetres scanned.
  CHECK((x_absent - x_rigid).cwiseAbs().maxCoeff() < 1e-6);

  // A released clamp holds nothing.
  std::vector<ClampPose> released = absent.poses;
  released[0].engaged = false;
  (void)absent.model.hold_clamps(absent.clamps, released);
  VecX g = VecX::Zero(x_absent.size());
  CHECK(absent.model.clamp_slip().evaluate(x_rigid + VecX::Constant(x_rigid.size(), 0.01), &g, nullptr,
                                           HessianMode::kExact) == 0.0);
  CHECK(absent.model.clamp_slip().coupling().evaluate(x_rigid + VecX::Constant(x_rigid.size(), 0.01), &g, nullptr,
                                                      HessianMode::kExact) == 0.0);
  CHECK(g.norm() == 0.0);
}

TEST_CASE("clamp slip: a hanging strip slips by the compliance times its weight", "[twin][clamp_slip]") {
  const double compliance_m_N = 0.01;
  HeldStrip rigid(0.0, hanging()), slipping(compliance_m_N, hanging());
  const VecX x_rigid = rigid.solve(), x_slip = slipping.solve();
  const double weight_N = slipping.model.total_mass_kg() * kStandardGravity;
  // Every point of the strip comes down by the same slip, c W (the patch moves as one).
  const Vec3 at_clamp = slipping.clamps[0].material_point_position(x_slip) - rigid.clamps[0].material_point_position(x_rigid);
  INFO("slip at the clamp (m): " << at_clamp.transpose() << ", c W = " << compliance_m_N * weight_N);
  CHECK(-at_clamp.z() == Approx(compliance_m_N * weight_N).epsilon(0.02));
  CHECK(std::abs(at_clamp.y()) < 1e-6);  // the jaws do not give across their faces
  const int bottom = slipping.model.vertex_count() - 1;
  CHECK(x_rigid(3 * bottom + 2) - x_slip(3 * bottom + 2) == Approx(compliance_m_N * weight_N).epsilon(0.02));
}

TEST_CASE("clamp slip: the equilibrium's tangent in the compliance matches re-solved equilibria",
          "[twin][clamp_slip]") {
  // At zero compliance (the score test's point), at present ones, and at the upper bound,
  // where the difference of dg/dc must step backward: a forward step was out of range.
  for (double compliance_m_N : {0.0, 1e-5, 0.01, kMaxClampSlipCompliance_m_N}) {
    HeldStrip s(compliance_m_N, inclined());
    const VecX x0 = s.solve();
    const DofMap dofs = s.model.hold_clamps(s.clamps, s.poses);
    EquilibriumSensitivity sensitivity(s.model, dofs, x0);
    const Eigen::MatrixXd tangent = sensitivity.tangents({MaterialParameter::kClampSlipCompliance});
    const double step_m_N = compliance_m_N < kMaxClampSlipCompliance_m_N ? 1e-5 : -1e-5;
    HeldStrip moved(compliance_m_N + step_m_N, inclined());
    const VecX x1 = moved.solve();
    const VecX secant = (x1 - x0) / step_m_N;
    INFO("compliance " << compliance_m_N << ": |tangent| " << tangent.col(0).norm() << ", |secant| " << secant.norm());
    REQUIRE(secant.norm() > 0.1);  // metres per (m/N): the strip does move
    CHECK((tangent.col(0) - secant).norm() < 0.02 * secant.norm());
  }
}

}  // namespace twin::clamp_slip_test
