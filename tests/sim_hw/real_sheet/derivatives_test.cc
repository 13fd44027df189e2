// Finite-difference checks of every energy of the independent sheet (sim_hw/real_sheet): each
// unit's gradient and Hessian, exact and projected, and the assembled model's with jaws of both
// kinds, slip, creep, markers and an implicit step. A planted bug must be caught.

#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "sim_hw/real_sheet/curvature_bending.h"
#include "sim_hw/real_sheet/jaw_pad.h"
#include "sim_hw/real_sheet/membrane_q4.h"
#include "sim_hw/real_sheet/sheet_model.h"
#include "tests/support/finite_difference.h"

namespace rs = sim_hw::real_sheet;
using twin::testing::finite_difference_errors;

namespace {

Eigen::Matrix3d composite_C() {
  twin::Material m;
  m.tensile_stiffness_u_N_m = 6000;
  m.tensile_stiffness_v_N_m = 3000;
  m.shear_stiffness_N_m = 2500;
  return rs::sheet_material_from(m).membrane_C_N_m;
}

// A grid cell or stencil, lifted onto a curved, stretched and sheared surface with noise.
Eigen::VectorXd curved(int nodes_u, int nodes_v, double du, double dv, std::mt19937_64& rng, double noise = 2e-4) {
  std::normal_distribution<double> n(0.0, noise);
  Eigen::VectorXd x(3 * nodes_u * nodes_v);
  for (int j = 0; j < nodes_v; ++j) {
    for (int i = 0; i < nodes_u; ++i) {
      const double u = i * du, v = j * dv;
      x.segment<3>(3 * (j * nodes_u + i)) =
          Eigen::Vector3d(1.01 * u + 0.05 * v, 0.98 * v, 3.0 * u * u - 2.0 * u * v + 1.5 * v * v) +
          Eigen::Vector3d(n(rng), n(rng), n(rng));
    }
  }
  return x;
}

// The solver's rotation gradient G is taken at omega = 0 about the current turn exp([z]x) R; the
// gradient of z -> E(exp([z]x) R) is J_l(z)^T G with the left Jacobian J_l = I + [z]x / 2 + O(z^2),
// which the finite differences of the gradient at z = -+ step see.
void left_jacobian_transpose(const Eigen::Vector3d& z, Eigen::VectorXd& g) {
  const Eigen::Vector3d G = g.tail<3>();
  g.tail<3>() = G - 0.5 * z.cross(G);
}

}  // namespace

TEST_CASE("real sheet: Q4 membrane gradient and Hessian match finite differences", "[real_sheet]") {
  std::mt19937_64 rng(7);
  const double du = 0.02, dv = 0.015;
  const Eigen::VectorXd cell = curved(2, 2, du, dv, rng);
  rs::Vec12 x;
  x << cell.segment<3>(0), cell.segment<3>(3), cell.segment<3>(9), cell.segment<3>(6);  // counter-clockwise
  const std::array<Eigen::Vector3d, 4> e0{Eigen::Vector3d(1e-3, -2e-3, 5e-4), Eigen::Vector3d::Zero(),
                                          Eigen::Vector3d(0, 1e-3, 0), Eigen::Vector3d(-1e-3, 0, 2e-3)};
  const auto f = [&](const Eigen::VectorXd& y, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
    rs::Vec12 gg;
    rs::Mat12 hh;
    const double e = rs::q4_membrane_energy(y, du, dv, composite_C(), &e0, g ? &gg : nullptr, h ? &hh : nullptr);
    if (g) *g = gg;
    if (h) *h = hh;
    return e;
  };
  const auto errors = finite_difference_errors(f, x, 1e-7);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-6);
  CHECK(errors.hessian < 1e-5);

  SECTION("zero at rest, and the projected Hessian is positive semi-definite in compression") {
    rs::Vec12 flat;
    flat << 0, 0, 0, du, 0, 0, du, dv, 0, 0, dv, 0;
    rs::Vec12 g;
    CHECK(rs::q4_membrane_energy(flat, du, dv, composite_C(), nullptr, &g, nullptr) == Approx(0).margin(1e-18));
    CHECK(g.norm() < 1e-12);
    rs::Vec12 compressed = 0.97 * flat;
    compressed[2] = 1e-4;
    rs::Mat12 h;
    rs::q4_membrane_energy(compressed, du, dv, composite_C(), nullptr, nullptr, &h, rs::Hessian::kProjected);
    CHECK(Eigen::SelfAdjointEigenSolver<rs::Mat12>(h).eigenvalues().minCoeff() > -1e-9 * h.norm());
    rs::q4_membrane_energy(compressed, du, dv, composite_C(), nullptr, nullptr, &h, rs::Hessian::kExact);
    CHECK(Eigen::SelfAdjointEigenSolver<rs::Mat12>(h).eigenvalues().minCoeff() < -1e-6 * h.norm());
  }
}

TEST_CASE("real sheet: curvature bending gradient and Hessian match finite differences", "[real_sheet]") {
  std::mt19937_64 rng(11);
  // Unequal spacings on each side, as a graded grid has them.
  rs::BendingNode node{0.02, 0.026, 0.025, 0.019, 1.5 * 0.02 * 0.025, Eigen::Vector3d(0.8, -0.3, 0.4)};
  Eigen::Matrix3d D;
  D << 8e-4, 2e-4, 0, 2e-4, 5e-4, 0, 0, 0, 3e-4;
  Eigen::VectorXd x = curved(3, 3, 0.02, 0.025, rng);
  for (int s = 0; s < 9; ++s) {  // onto the unequal spacings
    x[3 * s] += (s % 3 == 2 ? 0.006 : 0.0);
    x[3 * s + 1] += (s / 3 == 0 ? 0.006 : 0.0);
  }
  for (const double beta : {0.0, 0.05}) {
    const auto f = [&](const Eigen::VectorXd& y, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
      rs::Vec27 gg;
      rs::Mat27 hh;
      const double e = rs::curvature_bending_energy(y, node, D, beta, g ? &gg : nullptr, h ? &hh : nullptr);
      if (g) *g = gg;
      if (h) *h = hh;
      return e;
    };
    const auto errors = finite_difference_errors(f, x, 1e-7);
    INFO("beta " << beta << ": " << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-5);
  }
  SECTION("zero energy and force on the rest shape, positive semi-definite projection") {
    rs::BendingNode flat = node;
    flat.rest_k_1_m.setZero();
    Eigen::VectorXd plane(27);
    const double us[3] = {0.0, flat.du_before_m, flat.du_before_m + flat.du_after_m};
    const double vs[3] = {0.0, flat.dv_before_m, flat.dv_before_m + flat.dv_after_m};
    for (int s = 0; s < 9; ++s) plane.segment<3>(3 * s) = Eigen::Vector3d(us[s % 3], vs[s / 3], 0);
    // A rigid turn of the flat stencil.
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    for (int s = 0; s < 9; ++s) plane.segment<3>(3 * s) = R * plane.segment<3>(3 * s);
    rs::Vec27 g;
    CHECK(rs::curvature_bending_energy(plane, flat, D, 0.0, &g, nullptr) == Approx(0).margin(1e-20));
    CHECK(g.norm() < 1e-12);
    rs::Mat27 h;
    rs::curvature_bending_energy(x, node, D, 0.05, nullptr, &h, rs::Hessian::kProjected);
    CHECK(Eigen::SelfAdjointEigenSolver<rs::Mat27>(h).eigenvalues().minCoeff() > -1e-9 * h.norm());
  }
}

TEST_CASE("real sheet: jaw pads' gradient and Hessian match finite differences, rigid and pivot", "[real_sheet]") {
  std::mt19937_64 rng(5);
  const rs::Grid grid(0.1, 0.08, 0.02);
  rs::JawPadOptions options;
  options.grip_radius_m = 0.018;
  options.pad_stiffness_N_m3 = 1e6;  // soft, so the finite differences see the terms' curvature
  options.extension_m = 0.02;
  options.extension_strength = 0.7;
  options.slip_compliance_m_N = 0.5;
  const Eigen::VectorXd x = curved(grid.nu(), grid.nv(), grid.du(0), grid.dv(0), rng, 3e-3);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, -1, 0.5).normalized()).toRotationMatrix();
  const rs::Vec3 c(0.04, 0.05, 0.1);
  for (const rs::JawKind kind : {rs::JawKind::kRigid, rs::JawKind::kPivot}) {
    const rs::JawPad pad = rs::make_jaw_pad(grid, "A", rs::Vec2(0.05, 0.04), kind, options);
    REQUIRE(pad.tangential_share < 1.0);
    const std::vector<int> nodes = rs::pad_nodes(pad);
    const int n = static_cast<int>(nodes.size());
    const bool pivot = kind == rs::JawKind::kPivot;
    // Unknowns: the pad's nodes, then the turn omega (pivot), R(omega) = exp([omega]x) R.
    Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * n + (pivot ? 3 : 0));
    for (int k = 0; k < n; ++k) y.segment<3>(3 * k) = x.segment<3>(3 * nodes[k]);
    const auto f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
      Eigen::VectorXd full = x;
      for (int k = 0; k < n; ++k) full.segment<3>(3 * nodes[k]) = z.segment<3>(3 * k);
      const Eigen::Matrix3d Rz = pivot ? Eigen::Matrix3d(rs::rotation_exp(z.tail<3>()) * R) : R;
      if (g) *g = Eigen::VectorXd::Zero(z.size());
      if (h) *h = Eigen::MatrixXd::Zero(z.size(), z.size());
      const double e = rs::jaw_pad_energy(pad, full, c, Rz, nodes, g, h);
      if (g && pivot) left_jacobian_transpose(z.tail<3>(), *g);
      return e;
    };
    // The rotation derivatives are those at omega = 0, so check there.
    const auto errors = finite_difference_errors(f, y, 1e-7);
    INFO((pivot ? "pivot: " : "rigid: ") << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-5);
  }
}

TEST_CASE("real sheet: the assembled model's derivatives match finite differences", "[real_sheet]") {
  std::mt19937_64 rng(3);
  twin::Material m;
  m.tensile_stiffness_u_N_m = 900;
  m.tensile_stiffness_v_N_m = 600;
  m.shear_stiffness_N_m = 300;
  m.bending_rigidity_u_Nm = 2e-3;
  m.bending_rigidity_v_Nm = 1e-3;
  m.tensile_viscosity_Ns_m = 2;
  m.shear_viscosity_Ns_m = 1;
  m.mass_damping_1_s = 0.5;
  m.effects.rest_curvature_uu_1_m = 0.5;
  m.effects.bending_stiffening_m2 = 0.01;
  m.effects.marker_mass_kg = 1e-3;
  m.effects.relaxation_fraction = 0.4;
  m.effects.relaxation_time_s = 100;
  m.effects.clamp_slip_compliance_m_N = 0.3;
  const rs::Grid grid(0.12, 0.1, 0.03);
  rs::SheetModel model(grid, rs::sheet_material_from(m), {rs::Vec2(0.05, 0.05), rs::Vec2(0.1, 0.02)});
  model.set_age_s(60);
  const Eigen::VectorXd x = curved(grid.nu(), grid.nv(), grid.du(0), grid.dv(0), rng, 2e-3);
  rs::JawPadOptions o;
  o.grip_radius_m = 0.02;
  o.pad_stiffness_N_m3 = 1e5;
  o.slip_compliance_m_N = 0.3;
  std::vector<rs::JawHold> jaws(2);
  jaws[0].pad = rs::make_jaw_pad(grid, "A", rs::Vec2(0.02, 0.02), rs::JawKind::kRigid, o);
  jaws[0].centre_m = rs::Vec3(0.03, 0.01, 0.02);
  jaws[1].pad = rs::make_jaw_pad(grid, "B", rs::Vec2(0.1, 0.08), rs::JawKind::kPivot, o);
  jaws[1].centre_m = rs::Vec3(0.1, 0.09, 0.01);
  jaws[1].rotation = rs::rotation_exp(rs::Vec3(0.1, -0.2, 0.3));
  rs::StepTerms step;
  step.dt_s = 0.02;
  step.x_start = grid.flat_positions();
  step.v_start = Eigen::VectorXd::Constant(x.size(), 0.1);
  step.strain_start = model.cell_strains(step.x_start + Eigen::VectorXd::Constant(x.size(), 1e-3));
  for (const bool dynamic : {false, true}) {
    const auto f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
      std::vector<rs::JawHold> turned = jaws;
      turned[1].rotation = rs::rotation_exp(z.tail<3>()) * jaws[1].rotation;
      rs::BlockSparseMatrix H = model.hessian_pattern(turned);
      const double e = model.energy(z.head(x.size()), turned, g, h ? &H : nullptr, rs::Hessian::kExact,
                                    dynamic ? &step : nullptr);
      if (h) *h = H.dense();
      if (g) left_jacobian_transpose(z.tail<3>(), *g);
      return e;
    };
    Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size() + 3);
    y.head(x.size()) = x;
    const auto errors = finite_difference_errors(f, y, 1e-7);
    INFO((dynamic ? "implicit step: " : "static: ") << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-5);
  }
}

TEST_CASE("real sheet: the checker catches a planted bug in the bending Hessian", "[real_sheet]") {
  std::mt19937_64 rng(13);
  const rs::BendingNode node = rs::BendingNode::uniform(0.02, 0.02, 4e-4);
  const Eigen::Matrix3d D = Eigen::Vector3d(1e-3, 1e-3, 3.5e-4).asDiagonal();
  const Eigen::VectorXd x = curved(3, 3, 0.02, 0.02, rng);
  const auto f = [&](const Eigen::VectorXd& y, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
    rs::Vec27 gg;
    rs::Mat27 hh;
    // The bug: the Gauss-Newton Hessian where the exact one is due.
    const double e = rs::curvature_bending_energy(y, node, D, 0.0, g ? &gg : nullptr, h ? &hh : nullptr,
                                                  rs::Hessian::kProjected);
    if (g) *g = gg;
    if (h) *h = hh;
    return e;
  };
  const auto errors = finite_difference_errors(f, x, 1e-7);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-6);
  CHECK(errors.hessian > 1e-3);
}
