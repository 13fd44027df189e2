// Finite-difference checks of every energy of the reference sheet (sim_hw/spline_shell): the
// membrane and bending densities at a point, the assembled shell (rest curvature, a crease,
// stiffening, creep, marker masses). The projected Hessians are positive semi-definite; a
// planted bug must be caught.

#include <random>

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>

#include "sim_hw/real_sheet/kirchhoff_love_point.h"
#include "sim_hw/spline_shell/shell_model.h"
#include "tests/sim_hw/spline_shell/shell_fixtures.h"
#include "tests/support/finite_difference.h"

namespace ss = sim_hw::spline_shell;
namespace rs = sim_hw::real_sheet;
using shell_fixtures::composite;
using twin::testing::finite_difference_errors;

namespace {

// A patch lifted onto a curved, stretched and sheared surface with noise on the controls.
ss::VecX curved(const ss::SplinePatch& patch, std::mt19937_64& rng, double noise = 2e-4) {
  ss::VecX x = patch.interpolate([](const ss::Vec2& uv) {
    const double u = uv.x(), v = uv.y();
    return ss::Vec3(1.01 * u + 0.05 * v, 0.98 * v, 3.0 * u * u - 2.0 * u * v + 1.5 * v * v);
  });
  std::normal_distribution<double> n(0.0, noise);
  for (int i = 0; i < x.size(); ++i) x[i] += n(rng);
  return x;
}

ss::SplinePatch small_patch(int degree = 3) {
  return ss::SplinePatch(ss::KnotVector(degree, {0.0, 0.04, 0.07, 0.12}), ss::KnotVector(degree, {0.0, 0.05, 0.09}));
}

}  // namespace

TEST_CASE("spline shell: membrane density gradient and Hessian match finite differences", "[spline_shell]") {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0.0, 0.05);
  ss::Vec6 y;
  y << 1.02, 0.03, 0.1, -0.02, 0.97, 0.2;
  for (int i = 0; i < 6; ++i) y[i] += n(rng);
  const Eigen::Vector3d e0(1e-3, -2e-3, 5e-4);
  const auto f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
    ss::Vec6 gg;
    ss::Mat6 hh;
    const double e = ss::membrane_density(z, composite().membrane_C_N_m, e0, g ? &gg : nullptr, h ? &hh : nullptr);
    if (g) *g = gg;
    if (h) *h = hh;
    return e;
  };
  const auto errors = finite_difference_errors(f, y, 1e-7);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-7);
  CHECK(errors.hessian < 1e-6);

  SECTION("zero at rest, projected Hessian positive semi-definite in compression") {
    ss::Vec6 rest;
    rest << 1, 0, 0, 0, 1, 0;
    ss::Vec6 g;
    CHECK(ss::membrane_density(rest, composite().membrane_C_N_m, Eigen::Vector3d::Zero(), &g, nullptr) == 0.0);
    CHECK(g.norm() == 0.0);
    ss::Vec6 squeezed;
    squeezed << 0.9, 0, 0, 0.1, 0.95, 0;
    ss::Mat6 H;
    ss::membrane_density(squeezed, composite().membrane_C_N_m, Eigen::Vector3d::Zero(), nullptr, &H,
                         ss::Hessian::kProjected);
    CHECK(Eigen::SelfAdjointEigenSolver<ss::Mat6>(H).eigenvalues().minCoeff() > -1e-9);
    ss::membrane_density(squeezed, composite().membrane_C_N_m, Eigen::Vector3d::Zero(), nullptr, &H, ss::Hessian::kExact);
    CHECK(Eigen::SelfAdjointEigenSolver<ss::Mat6>(H).eigenvalues().minCoeff() < -1.0);
  }
}

TEST_CASE("spline shell: Kirchhoff-Love density gradient and Hessian match finite differences", "[spline_shell]") {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  rs::Vec15 y;
  for (int i = 0; i < 9; ++i) y[i] = 5.0 * n(rng);  // second derivatives, 1/m
  y.segment<3>(9) = Eigen::Vector3d(1.0, 0.05, 0.1) + 0.03 * Eigen::Vector3d(n(rng), n(rng), n(rng));
  y.segment<3>(12) = Eigen::Vector3d(-0.02, 0.98, 0.2) + 0.03 * Eigen::Vector3d(n(rng), n(rng), n(rng));
  const Eigen::Vector3d rest(0.5, -1.0, 0.3);
  const Eigen::Matrix3d D = composite().bending_D_Nm();
  const auto f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
    rs::Vec15 gg;
    rs::Mat15 hh;
    const double e = rs::kirchhoff_love_density(z, rest, D, 0.002, g ? &gg : nullptr, h ? &hh : nullptr);
    if (g) *g = gg;
    if (h) *h = hh;
    return e;
  };
  const auto errors = finite_difference_errors(f, y, 1e-7);
  INFO(errors.report());
  CHECK(errors.gradient < 1e-7);
  CHECK(errors.hessian < 1e-6);
}

TEST_CASE("spline shell: the assembled shell's gradient and Hessian match finite differences", "[spline_shell]") {
  for (int degree : {2, 3}) {
    std::mt19937_64 rng(9);
    const ss::SplinePatch patch = small_patch(degree);
    rs::SheetMaterial material = composite();
    material.rest_curvature_1_m << 2.0, 0.5, 0.5, -1.0;
    material.creases.push_back(rs::CreaseBand{ss::Vec2(0.06, 0.04), 0.3, 0.8, 0.03});
    material.stiffening_m2 = 1e-3;
    material.creep_fraction = 0.3;
    material.marker_mass_kg = 2e-4;
    ss::ShellModel model(patch, material, {ss::Vec2(0.03, 0.02), ss::Vec2(0.1, 0.08)});
    model.set_age_s(30.0);
    const ss::VecX x = curved(patch, rng);
    ss::BlockSparseMatrix pattern = model.hessian_pattern();
    const auto f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
      if (g) *g = Eigen::VectorXd::Zero(z.size());
      if (h) pattern.set_zero();
      const double e = model.energy(z, g, h ? &pattern : nullptr);
      if (h) *h = pattern.dense();
      return e;
    };
    const auto errors = finite_difference_errors(f, x, 1e-7);
    INFO("degree " << degree << ": " << errors.report());
    CHECK(errors.gradient < 1e-6);
    CHECK(errors.hessian < 1e-5);

    // The projected Hessian is positive semi-definite.
    pattern.set_zero();
    model.energy(x, nullptr, &pattern, ss::Hessian::kProjected);
    const Eigen::MatrixXd H = pattern.dense();
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff() > -1e-8 * H.norm());
  }
}

TEST_CASE("spline shell: the checker catches a planted bug in the assembled Hessian", "[spline_shell]") {
  std::mt19937_64 rng(21);
  const ss::SplinePatch patch = small_patch();
  ss::ShellModel model(patch, composite());
  const ss::VecX x = curved(patch, rng);
  ss::BlockSparseMatrix pattern = model.hessian_pattern();
  const auto f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
    if (g) *g = Eigen::VectorXd::Zero(z.size());
    if (h) pattern.set_zero();
    const double e = model.energy(z, g, h ? &pattern : nullptr);
    if (h) {
      *h = pattern.dense();
      (*h)(4, 4) += 0.1 * h->cwiseAbs().maxCoeff();  // the bug: one diagonal entry off
    }
    return e;
  };
  const auto errors = finite_difference_errors(f, x, 1e-7);
  INFO(errors.report());
  CHECK(errors.hessian > 1e-4);
}
