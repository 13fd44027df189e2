// KUKA iiwa kinematics: forward kinematics against poses worked out by hand, the Jacobian against
// finite differences, inverse kinematics round trips on random reachable poses (seeded), an
// unreachable pose and a joint-limited pose reported as such, and the joint command limiter.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "drivers/iiwa_inverse_kinematics.h"
#include "drivers/iiwa_kinematics.h"
#include "drivers/joint_command_limiter.h"

using namespace drivers;

namespace {

constexpr double kPi = M_PI;

JointVector random_configuration(const IiwaParameters& p, std::mt19937& rng, double fraction) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  JointVector q;
  for (int i = 0; i < kIiwaJoints; ++i) q[i] = fraction * u(rng) * p.position_max_rad[i];
  return q;
}

double rotation_angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a * b.transpose()).angle();
}

}  // namespace

TEST_CASE("the zero configuration points straight up to d1 + d3 + d5 + d7", "[iiwa]") {
  for (IiwaModel model : {IiwaModel::kIiwa7R800, IiwaModel::kIiwa14R820}) {
    const IiwaParameters p = iiwa_parameters(model);
    const IiwaArm arm(p);
    const Eigen::Isometry3d flange = arm.flange_in_cell(JointVector::Zero());
    const double height = model == IiwaModel::kIiwa7R800 ? 0.34 + 0.4 + 0.4 + 0.126
                                                          : 0.36 + 0.42 + 0.4 + 0.126;
    CHECK(flange.translation().isApprox(Eigen::Vector3d(0, 0, height), 1e-12));
    CHECK(flange.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  }
}

TEST_CASE("forward kinematics follows the iiwa joint axes and the base pose", "[iiwa]") {
  const IiwaParameters p = iiwa_parameters(IiwaModel::kIiwa7R800);
  const IiwaArm arm(p);
  const double forearm = p.d5_m + p.d7_m;
  JointVector q = JointVector::Zero();
  SECTION("A2 +90 deg (about +y) lays the arm along +x at shoulder height") {
    q[1] = kPi / 2;
    const Eigen::Isometry3d f = arm.flange_in_cell(q);
    CHECK(f.translation().isApprox(Eigen::Vector3d(p.d3_m + forearm, 0, p.d1_m), 1e-12));
    CHECK(f.linear().col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  }
  SECTION("A4 +90 deg (about -y) bends the forearm toward -x at elbow height") {
    q[3] = kPi / 2;
    const Eigen::Isometry3d f = arm.flange_in_cell(q);
    CHECK(f.translation().isApprox(Eigen::Vector3d(-forearm, 0, p.d1_m + p.d3_m), 1e-12));
  }
  SECTION("A1 turns the bent arm about the vertical, A7 turns only the flange") {
    q[1] = kPi / 2;
    q[0] = kPi / 2;
    q[6] = 0.7;
    const Eigen::Isometry3d f = arm.flange_in_cell(q);
    CHECK(f.translation().isApprox(Eigen::Vector3d(0, p.d3_m + forearm, p.d1_m), 1e-12));
    JointVector q_no_a7 = q;
    q_no_a7[6] = 0;
    CHECK(f.translation().isApprox(arm.flange_in_cell(q_no_a7).translation(), 1e-12));
    CHECK(rotation_angle(f.linear(), arm.flange_in_cell(q_no_a7).linear()) ==
          Approx(0.7).margin(1e-12));
  }
  SECTION("the base pose in the cell moves the whole arm") {
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translate(Eigen::Vector3d(1.0, -0.5, 0.8));
    base.rotate(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()));
    const IiwaArm placed(p, base);
    q << 0.3, -0.5, 0.2, 1.1, -0.4, 0.9, 0.1;
    CHECK(placed.flange_in_cell(q).isApprox(base * arm.flange_in_cell(q), 1e-12));
  }
}

TEST_CASE("the Jacobian matches finite differences of forward kinematics", "[iiwa]") {
  std::mt19937 rng(11);
  for (IiwaModel model : {IiwaModel::kIiwa7R800, IiwaModel::kIiwa14R820}) {
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translate(Eigen::Vector3d(0.2, 0.1, 0.5));
    base.rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()));
    const IiwaArm arm(iiwa_parameters(model), base);
    for (int trial = 0; trial < 10; ++trial) {
      const JointVector q = random_configuration(arm.parameters(), rng, 0.9);
      const IiwaJacobian j = arm.jacobian(q);
      const double h = 1e-6;
      for (int i = 0; i < kIiwaJoints; ++i) {
        JointVector plus = q, minus = q;
        plus[i] += h;
        minus[i] -= h;
        const Eigen::Isometry3d fp = arm.flange_in_cell(plus), fm = arm.flange_in_cell(minus);
        const Eigen::Vector3d v = (fp.translation() - fm.translation()) / (2 * h);
        const Eigen::AngleAxisd turn(fp.linear() * fm.linear().transpose());
        const Eigen::Vector3d w = turn.angle() * turn.axis() / (2 * h);
        CHECK((j.block<3, 1>(0, i) - v).norm() < 1e-7);
        CHECK((j.block<3, 1>(3, i) - w).norm() < 1e-7);
      }
    }
  }
}

TEST_CASE("inverse kinematics recovers random reachable poses within the limits", "[iiwa]") {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  for (IiwaModel model : {IiwaModel::kIiwa7R800, IiwaModel::kIiwa14R820}) {
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translate(Eigen::Vector3d(-0.6, 0.4, 0.0));
    const IiwaArm arm(iiwa_parameters(model), base);
    int converged = 0;
    const int trials = 200;
    for (int trial = 0; trial < trials; ++trial) {
      const JointVector q_true = random_configuration(arm.parameters(), rng, 0.9);
      const Eigen::Isometry3d target = arm.flange_in_cell(q_true);
      JointVector seed = q_true;
      for (int i = 0; i < kIiwaJoints; ++i) seed[i] += offset(rng);
      const IkResult r = solve_inverse_kinematics(arm, target, seed);
      REQUIRE(arm.within_limits(r.q));
      if (r.status != IkStatus::kConverged) continue;
      ++converged;
      const Eigen::Isometry3d reached = arm.flange_in_cell(r.q);
      CHECK((reached.translation() - target.translation()).norm() <= 1e-4);
      CHECK(rotation_angle(reached.linear(), target.linear()) <= 1e-3);
    }
    INFO(to_string(model) << ": " << converged << " of " << trials << " converged");
    CHECK(converged == trials);
  }
}

TEST_CASE("with restarts, inverse kinematics reaches random poses from a fixed home seed",
          "[iiwa]") {
  std::mt19937 rng(99);
  const IiwaArm arm(iiwa_parameters(IiwaModel::kIiwa7R800));
  JointVector home;
  home << 0, 0.5, 0, -1.2, 0, 0.8, 0;
  IkOptions options;
  options.restarts = 10;
  const int trials = 200;
  int converged = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Isometry3d target =
        arm.flange_in_cell(random_configuration(arm.parameters(), rng, 0.9));
    const IkResult r = solve_inverse_kinematics(arm, target, home, options);
    REQUIRE(arm.within_limits(r.q));
    if (r.status != IkStatus::kConverged) continue;
    ++converged;
    CHECK((arm.flange_in_cell(r.q).translation() - target.translation()).norm() <= 1e-4);
  }
  CHECK(converged == trials);
}

TEST_CASE("a pose out of reach is reported unreachable with its residual", "[iiwa]") {
  const IiwaArm arm(iiwa_parameters(IiwaModel::kIiwa14R820));
  const IiwaParameters& p = arm.parameters();
  // 2 m out along +x at shoulder height, flange pointing along +x: the stretched arm gets
  // within 2 - (d3 + d5 + d7) of it.
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  target.translate(Eigen::Vector3d(2.0, 0, p.d1_m));
  target.rotate(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
  JointVector seed = JointVector::Zero();
  seed[1] = 0.5;
  const IkResult r = solve_inverse_kinematics(arm, target, seed);
  CHECK(r.status == IkStatus::kUnreachable);
  CHECK(r.position_residual_m == Approx(2.0 - arm.reach_m()).margin(1e-3));
  CHECK(arm.within_limits(r.q));
}

TEST_CASE("a pose that needs a joint past its limit is reported as a limit", "[iiwa]") {
  // With A4 limited to +-10 deg the wrist cannot come as close to the shoulder as a 80 deg elbow
  // bend puts it (the shoulder-wrist distance depends on A4 alone).
  IiwaParameters p = iiwa_parameters(IiwaModel::kIiwa7R800);
  p.position_min_rad[3] = -10 * kPi / 180;
  p.position_max_rad[3] = 10 * kPi / 180;
  const IiwaArm narrow(p);
  const IiwaArm full(iiwa_parameters(IiwaModel::kIiwa7R800));
  JointVector q_target;
  q_target << 0.2, 0.4, 0.0, 80 * kPi / 180, 0.1, 0.5, 0.0;
  const Eigen::Isometry3d target = full.flange_in_cell(q_target);

  const IkResult r = solve_inverse_kinematics(narrow, target, JointVector::Zero());
  CHECK(r.status == IkStatus::kJointLimit);
  CHECK(r.limited_joint == 3);
  CHECK(r.position_residual_m > 0.01);
  CHECK(narrow.within_limits(r.q));
  // The same pose with the real limits is reachable.
  CHECK(solve_inverse_kinematics(full, target, JointVector::Zero()).status ==
        IkStatus::kConverged);
}

TEST_CASE("the command limiter respects position and velocity limits", "[iiwa]") {
  const IiwaParameters p = iiwa_parameters(IiwaModel::kIiwa14R820);
  const double dt = 0.005;  // 200 Hz command rate, s
  JointVector current = JointVector::Zero();

  SECTION("a small step passes unchanged") {
    JointVector target = current;
    target[0] = 0.5 * p.velocity_max_rad_s[0] * dt;
    const LimitedCommand c = limit_joint_command(p, current, target, dt);
    CHECK(c.q == target);
    CHECK_FALSE(c.position_clamped);
    CHECK_FALSE(c.velocity_clamped);
  }
  SECTION("a large step is shortened along its direction to the slowest joint's limit") {
    JointVector target;
    target << 0.5, -0.5, 0.5, 0.5, 0.5, 0.5, 0.5;
    const LimitedCommand c = limit_joint_command(p, current, target, dt);
    CHECK(c.velocity_clamped);
    for (int i = 0; i < kIiwaJoints; ++i) {
      CHECK(std::abs(c.q[i] - current[i]) <= p.velocity_max_rad_s[i] * dt + 1e-15);
    }
    // A4 is the slowest joint of the R820 (75 deg/s): it moves at exactly its limit.
    CHECK(std::abs(c.q[3]) == Approx(p.velocity_max_rad_s[3] * dt));
    CHECK((c.q / c.q.norm()).isApprox(target / target.norm(), 1e-12));
  }
  SECTION("a target past the position limits is clamped, then followed at speed") {
    current = p.position_max_rad - JointVector::Constant(0.001);
    const JointVector target = p.position_max_rad + JointVector::Constant(1.0);
    JointVector q = current;
    for (int step = 0; step < 100; ++step) {
      const LimitedCommand c = limit_joint_command(p, q, target, dt);
      CHECK(c.position_clamped);
      q = c.q;
    }
    CHECK(q.isApprox(p.position_max_rad, 1e-12));
  }
  SECTION("half speed halves the step") {
    JointVector target = JointVector::Constant(1.0);
    const LimitedCommand c = limit_joint_command(p, current, target, dt, 0.5);
    CHECK(std::abs(c.q[3]) == Approx(0.5 * p.velocity_max_rad_s[3] * dt));
  }
  SECTION("a non-finite target or dt keeps the current command") {
    JointVector target = JointVector::Constant(0.1);
    target[2] = std::nan("");
    CHECK(limit_joint_command(p, current, target, dt).q == current);
    CHECK(limit_joint_command(p, current, JointVector::Constant(0.1), 0.0).q == current);
  }
}

TEST_CASE("iiwa model names parse, and an unknown one is named in the error", "[iiwa]") {
  CHECK(iiwa_model_from_string("iiwa7") == IiwaModel::kIiwa7R800);
  CHECK(iiwa_model_from_string("R820") == IiwaModel::kIiwa14R820);
  CHECK_THROWS_WITH(iiwa_model_from_string("iiwa9"), Catch::Contains("'iiwa9'"));
  const IiwaParameters p7 = iiwa_parameters(IiwaModel::kIiwa7R800);
  CHECK(p7.velocity_max_rad_s[5] == Approx(180 * kPi / 180));
  CHECK(p7.position_max_rad[6] == Approx(175 * kPi / 180));
}
