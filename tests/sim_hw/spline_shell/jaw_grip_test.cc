// The lab's wide and slipping jaws on the reference sheet (sim_hw/spline_shell/jaw_grip.h): the
// hold's shape, the ring's edges as knots, the springs' derivatives against finite differences,
// a slipping jaw that lets the ply slide by its compliance times the pull, and wide jaws that hold
// the ply beyond the pad.

#include <cmath>
#include <random>

#include <catch2/catch.hpp>

#include "sim_hw/spline_shell/jaw_grip.h"
#include "sim_hw/spline_shell/shell_equilibrium.h"
#include "tests/sim_hw/spline_shell/shell_fixtures.h"
#include "tests/support/finite_difference.h"

namespace ss = sim_hw::spline_shell;
using shell_fixtures::composite;

namespace {

ss::JawGrip wide_and_slipping() {
  ss::JawGrip grip;
  grip.extension_m = 0.02;
  grip.extension_strength = 0.8;
  grip.slip_compliance_m_N = 5e-4;
  return grip;
}

// A sheet held by one jaw at its top edge's middle, its pad face vertical (the sheet hangs in
// the pad's plane: its weight pulls along the jaw faces) or level (the sheet droops out of it).
struct OneJaw {
  static constexpr double W = 0.2, H = 0.16;
  ss::SquareJaw jaw = ss::square_jaw("A", ss::Vec2(0.1, 0.13), 0.015, W, H);
  ss::ShellModel model;
  ss::ShellHolds holds;

  OneJaw(const sim_hw::real_sheet::SheetMaterial& material, bool vertical, double extension_m)
      : model(ss::SplinePatch(ss::jaw_knots(3, W, 0, {jaw}, 0.02, 0.005, extension_m),
                              ss::jaw_knots(3, H, 1, {jaw}, 0.02, 0.005, extension_m)),
              material) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (vertical) R.col(1) = ss::Vec3(0, 0, 1), R.col(2) = ss::Vec3(0, -1, 0);  // u along x, v up
    holds.jaws.push_back({jaw, ss::Vec3(0.1, 0.0, 0.5), R});
  }
  ss::VecX hang() {
    // The flat sheet put in the pad's plane, then let go into gravity (overdamped).
    ss::VecX x = model.patch().interpolate([&](const ss::Vec2& uv) {
      const ss::Vec3 d(uv.x() - jaw.material_point_m.x(), uv.y() - jaw.material_point_m.y(), 0.0);
      return ss::Vec3(holds.jaws[0].centre_m + holds.jaws[0].rotation * d);
    });
    ss::ShellSolveOptions options;
    options.initial_damping_1_s2 = 100.0;
    const ss::ShellSolveReport report = ss::solve_shell(model, holds, x, options);
    INFO(report.message);
    REQUIRE(report.converged);
    return x;
  }
};

}  // namespace

TEST_CASE("spline shell: the jaws' grip holds the pad, falls off across the ring and ends there", "[spline_shell]") {
  const ss::JawGrip grip = wide_and_slipping();
  const ss::SquareJaw jaw = ss::square_jaw("A", ss::Vec2(0.1, 0.1), 0.015, 0.3, 0.3);
  const double a = jaw.half_side_m, w = grip.extension_m;
  const ss::Vec2 m = jaw.material_point_m;
  CHECK(ss::grip_hold(grip, jaw, m + ss::Vec2(0.9 * a, -a)) == 1.0);
  CHECK(ss::grip_hold(grip, jaw, m + ss::Vec2(a + 0.5 * w, 0.0)) == Approx(0.8 * std::sqrt(0.75)));
  CHECK(ss::grip_hold(grip, jaw, m + ss::Vec2(a + 0.5 * w, -a - 0.5 * w)) == Approx(0.8 * 0.75));
  CHECK(ss::grip_hold(grip, jaw, m + ss::Vec2(0.0, a + 1.01 * w)) == 0.0);
  ss::JawGrip narrow;
  CHECK(ss::grip_hold(narrow, jaw, m + ss::Vec2(a + 0.1 * w, 0.0)) == 0.0);
  CHECK_FALSE(narrow.widens());
  CHECK(narrow.fixes_controls());
  CHECK_FALSE(grip.fixes_controls());

  SECTION("the material's jaws, and a negative one refused by name") {
    sim_hw::real_sheet::SheetMaterial material = composite();
    material.pad_extension_m = 0.03;
    material.pad_strength = 1.2;
    material.slip_compliance_m_N = 2e-4;
    const ss::JawGrip g = ss::jaw_grip(material);
    CHECK(g.extension_m == 0.03);
    CHECK(g.extension_strength == 1.2);
    CHECK(g.slip_compliance_m_N == 2e-4);
    material.slip_compliance_m_N = -1e-4;
    CHECK_THROWS_WITH(ss::jaw_grip(material), Catch::Contains("slip compliance"));
  }
}

TEST_CASE("spline shell: wide jaws' ring edges are simple knots, the pad's stay double", "[spline_shell]") {
  const ss::SquareJaw jaw = ss::square_jaw("A", ss::Vec2(0.1, 0.1), 0.015, 0.3, 0.3);
  const ss::KnotVector k = ss::jaw_knots(3, 0.3, 0, {jaw}, 0.02, 0.005, 0.02);
  const double a = jaw.half_side_m;
  const auto multiplicity_at = [&](double u) {
    for (std::size_t i = 0; i < k.breaks().size(); ++i) {
      if (std::abs(k.breaks()[i] - u) < 1e-12) return k.multiplicities()[i];
    }
    return 0;
  };
  CHECK(multiplicity_at(0.1 - a) == 2);
  CHECK(multiplicity_at(0.1 + a) == 2);
  CHECK(multiplicity_at(0.1 - a - 0.02) == 1);
  CHECK(multiplicity_at(0.1 + a + 0.02) == 1);
  CHECK(multiplicity_at(0.1 + a + 0.02 - 0.004) == 0);  // no sliver beside a ring edge
  // Bisection keeps them.
  const ss::KnotVector f = ss::refined(k);
  CHECK(f.element_count() == 2 * k.element_count());
}

TEST_CASE("spline shell: the grip springs' gradient and Hessian match finite differences", "[spline_shell]") {
  const ss::SquareJaw jaw = ss::square_jaw("A", ss::Vec2(0.05, 0.06), 0.01, 0.12, 0.1);
  const ss::SplinePatch patch(ss::jaw_knots(3, 0.12, 0, {jaw}, 0.02, 0.005, 0.015),
                              ss::jaw_knots(3, 0.1, 1, {jaw}, 0.02, 0.005, 0.015));
  ss::JawGrip grip = wide_and_slipping();
  grip.extension_m = 0.015;
  grip.pad_stiffness_N_m3 = 1e6;  // the check's scale, not the lab's
  std::mt19937_64 rng(4);
  std::normal_distribution<double> n(0.0, 2e-3);
  ss::VecX x = patch.flat_positions();
  for (int i = 0; i < x.size(); ++i) x[i] += n(rng);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, ss::Vec3(0.3, 1, -0.2).normalized()).toRotationMatrix();
  const ss::Vec3 c(0.01, -0.02, 0.03);
  for (bool slips : {true, false}) {
    grip.slip_compliance_m_N = slips ? 5e-4 : 0.0;
    const auto f = [&](const Eigen::VectorXd& y, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
      ss::BlockSparseMatrix H(patch.control_count(), [&] {
        std::vector<std::vector<int>> groups;
        for (int e = 0; e < patch.element_count(); ++e) groups.push_back(patch.element_controls(e));
        return groups;
      }());
      if (g) *g = Eigen::VectorXd::Zero(y.size());
      const double e = ss::grip_energy(patch, grip, jaw, c, R, y, g, h ? &H : nullptr);
      if (h) *h = H.dense();
      return e;
    };
    const auto errors = twin::testing::finite_difference_errors(f, x, 1e-6);
    INFO((slips ? "slipping: " : "wide: ") << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-6);
    CHECK(f(x, nullptr, nullptr) > 0);
  }
  // A grip that neither widens nor slips adds nothing.
  ss::VecX g = ss::VecX::Zero(x.size());
  CHECK(ss::grip_energy(patch, ss::JawGrip{}, jaw, c, R, x, &g, nullptr) == 0.0);
  CHECK(g.isZero());
}

TEST_CASE("spline shell: a slipping jaw lets the ply slide by its compliance times the pull", "[spline_shell]") {
  sim_hw::real_sheet::SheetMaterial material = composite();
  material.slip_compliance_m_N = 2e-3;  // 2 mm per newton
  OneJaw rig(material, true, 0.0);
  const ss::VecX x = rig.hang();
  const ss::JawGrip grip = ss::jaw_grip(material);
  REQUIRE_FALSE(grip.fixes_controls());
  // A stable equilibrium: the springs stand in for the fixed controls in the Hessian too.
  const double lambda = ss::lowest_eigenvalue_1_s2(rig.model, rig.holds, x);
  INFO("lowest eigenvalue " << lambda << " 1/s^2");
  CHECK(lambda > 0);
  // The jaw carries the weight, through its springs alone.
  const double weight_N = rig.model.total_weight_N();
  const ss::Vec3 lift = ss::holding_force_N(rig.model, rig.holds, x);
  CHECK(lift.z() == Approx(weight_N).epsilon(1e-6));
  CHECK(std::abs(lift.x()) < 1e-6 * weight_N);
  // The springs' stiffness-weighted mean slide along the faces is the compliance times the pull.
  // The pad's centre slides down by about as much; without slip it stays on the jaw.
  const double slid_m = (rig.model.patch().position(x, rig.jaw.material_point_m) - rig.holds.jaws[0].centre_m).z();
  INFO("weight " << weight_N << " N, the pad's centre slid " << slid_m * 1e3 << " mm");
  CHECK(slid_m == Approx(-material.slip_compliance_m_N * weight_N).epsilon(0.05));
  OneJaw rigid(composite(), true, 0.0);
  const ss::VecX held = rigid.hang();
  CHECK(std::abs((rigid.model.patch().position(held, rigid.jaw.material_point_m) - rigid.holds.jaws[0].centre_m).z()) <
        1e-12);
}

TEST_CASE("spline shell: wide jaws hold the ply level beyond the pad where narrow ones let it droop", "[spline_shell]") {
  sim_hw::real_sheet::SheetMaterial material = composite();
  material.pad_extension_m = 0.03;
  material.pad_strength = 1.0;
  OneJaw wide(material, false, material.pad_extension_m);
  OneJaw narrow(composite(), false, material.pad_extension_m);  // same knots, no ring
  const ss::VecX xw = wide.hang(), xn = narrow.hang();
  // Halfway across the ring below the pad, and far below it.
  const ss::Vec2 ring = wide.jaw.material_point_m - ss::Vec2(0.0, wide.jaw.half_side_m + 0.015);
  const ss::Vec2 far(0.1, 0.01);
  const double drop_wide = 0.5 - wide.model.patch().position(xw, ring).z();
  const double drop_narrow = 0.5 - narrow.model.patch().position(xn, ring).z();
  INFO("halfway across the ring: drop " << drop_wide * 1e3 << " mm with wide jaws, " << drop_narrow * 1e3 << " mm without");
  CHECK(drop_wide < 1e-4);
  CHECK(drop_narrow > 1e-3);
  CHECK(ss::holding_force_N(wide.model, wide.holds, xw).z() == Approx(wide.model.total_weight_N()).epsilon(1e-6));
  // The free end hangs lower from narrow jaws (a longer lever droops).
  CHECK(narrow.model.patch().position(xn, far).z() < wide.model.patch().position(xw, far).z());
}
