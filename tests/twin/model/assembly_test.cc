#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <random>

#include "tests/support/finite_difference.h"
#include "tests/support/random_states.h"
#include "twin/model/clamp.h"
#include "twin/solvers/newton_solver.h"
#include "twin/model/shell_model.h"

namespace twin {
namespace {

// The assembled sparse Hessian over free vertices must equal the finite-difference Hessian of
// the assembled gradient: this checks the sparsity pattern, the slot tables, the transposed
// blocks and the dropping of fixed vertices, on top of the per-element checks.
TEST_CASE("assembled Hessian over free vertices matches finite differences", "[twin][assembly]") {
  Material material;
  material.tensile_stiffness_u_N_m = 3000.0;
  material.tensile_stiffness_v_N_m = 2000.0;
  material.shear_stiffness_N_m = 500.0;
  material.bending_rigidity_u_Nm = 2e-3;
  material.bending_rigidity_v_Nm = 1e-3;
  const ShellModel model(make_rectangular_sheet(0.2, 0.15, 0.05), material);
  const Objective objective(model.potential_terms());
  std::mt19937 rng(1);
  const int n = model.vertex_count();
  std::vector<char> fixed(n, 0);
  fixed[0] = fixed[n / 2] = fixed[n - 1] = 1;
  const DofMap dofs(fixed);
  HessianPattern pattern(dofs, objective.stencils());
  const VecX x0 = testing::random_deformed(model.mesh().rest_uv, 0.2, 0.05, rng);

  for (HessianMode mode : {HessianMode::kExact}) {
    objective.evaluate(x0, nullptr, &pattern, mode);
    const Eigen::MatrixXd upper = Eigen::MatrixXd(pattern.matrix());
    const Eigen::MatrixXd assembled = upper.selfadjointView<Eigen::Upper>();
    // Finite differences of the free gradient along free DOFs.
    const int nf = dofs.free_dof_count();
    Eigen::MatrixXd fd(nf, nf);
    VecX grad_p(3 * n), grad_m(3 * n);
    for (int v = 0; v < n; ++v) {
      const int f = dofs.free_index(v);
      if (f < 0) continue;
      for (int k = 0; k < 3; ++k) {
        const double h = 1e-7;
        VecX xp = x0, xm = x0;
        xp(3 * v + k) += h;
        xm(3 * v + k) -= h;
        objective.evaluate(xp, &grad_p, nullptr, mode);
        objective.evaluate(xm, &grad_m, nullptr, mode);
        fd.col(3 * f + k) = (gather_free(dofs, grad_p) - gather_free(dofs, grad_m)) / (2 * h);
      }
    }
    const double error = (fd - assembled).norm() / assembled.norm();
    INFO("relative error " << error);
    CHECK(error < 1e-6);
  }
}

TEST_CASE("assembled projected Hessian is positive semi-definite", "[twin][assembly]") {
  Material material;
  material.bending_rigidity_u_Nm = material.bending_rigidity_v_Nm = 2e-3;
  const ShellModel model(make_rectangular_sheet(0.2, 0.15, 0.05), material);
  const Objective objective(model.potential_terms());
  std::mt19937 rng(2);
  // Compressed and crumpled: membrane stresses negative, hinges bent both ways.
  const VecX x = 0.85 * testing::random_deformed(model.mesh().rest_uv, 0.2, 0.08, rng);
  const DofMap dofs(std::vector<char>(model.vertex_count(), 0));
  HessianPattern pattern(dofs, objective.stencils());
  for (HessianMode mode : {HessianMode::kExact, HessianMode::kProjected}) {
    objective.evaluate(x, nullptr, &pattern, mode);
    const Eigen::MatrixXd upper(pattern.matrix());
    const Eigen::MatrixXd h = upper.selfadjointView<Eigen::Upper>();
    const double lowest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues().minCoeff();
    INFO((mode == HessianMode::kExact ? "exact" : "projected") << ": lowest eigenvalue " << lowest);
    if (mode == HessianMode::kExact) {
      CHECK(lowest < -1e-3 * h.norm() / h.rows());  // the state really is indefinite
    } else {
      CHECK(lowest > -1e-9 * h.norm());
    }
  }
}

}  // namespace
}  // namespace twin
