#include <catch2/catch.hpp>

#include "twin/model/shell_model.h"
#include "twin/model/objective.h"
#include "twin/solvers/background_factorizer.h"

namespace twin {
namespace {

// A small SPD system on a sheet's Hessian pattern: the membrane's projected Hessian of a flat
// sheet plus `diagonal` on the diagonal (the inertia of an implicit step), N/m.
struct SmallSystem {
  ShellModel model{make_rectangular_sheet(0.2, 0.15, 0.05), Material{}};
  DofMap dofs{std::vector<char>(model.vertex_count(), 0)};
  Objective objective{model.potential_terms()};
  HessianPattern hessian{dofs, objective.stencils()};

  const HessianPattern::Matrix& matrix(double diagonal) {
    objective.evaluate(place_flat(model.mesh(), SheetPlacement{}), nullptr, &hessian, HessianMode::kProjected);
    HessianPattern::Matrix& m = hessian.matrix();
    for (int j = 0; j < m.outerSize(); ++j) m.valuePtr()[m.outerIndexPtr()[j + 1] - 1] += diagonal;
    return m;
  }
};

// Residual of factor * y = rhs solved for the matrix it should be the factor of.
double solve_residual(const SparseCholesky& factor, const HessianPattern::Matrix& upper) {
  const VecX rhs = VecX::Ones(upper.rows());
  const VecX y = factor.solve(rhs);
  return (upper.selfadjointView<Eigen::Upper>() * y - rhs).norm() / rhs.norm();
}

TEST_CASE("background factorisations are handed over by ticket, in order", "[twin][solver]") {
  SmallSystem system;
  BackgroundFactorizer worker;
  worker.reset(system.matrix(1.0));
  const HessianPattern::Matrix soft = system.matrix(1.0), stiff = system.matrix(100.0);
  worker.submit(soft, 1);
  worker.submit(stiff, 2);
  std::unique_ptr<SparseCholesky> factor;
  // Submitting ticket 2 drops ticket 1 (only the newest is wanted); the factor is stiff's.
  const BackgroundFactorizer::Taken second = worker.take(factor, 2);
  REQUIRE(second.found);
  REQUIRE(second.ok);
  REQUIRE(factor);
  CHECK(solve_residual(*factor, stiff) < 1e-10);
  CHECK(solve_residual(*factor, soft) > 1e-3);
  CHECK_FALSE(worker.take(factor, 1).found);  // already dropped
  CHECK_FALSE(worker.take(factor, 7).found);  // never submitted: no wait, nothing found
}

TEST_CASE("a background factorisation of an indefinite matrix is reported, not handed over", "[twin][solver]") {
  SmallSystem system;
  BackgroundFactorizer worker;
  worker.reset(system.matrix(1.0));
  const HessianPattern::Matrix good = system.matrix(1.0), bad = system.matrix(-1e9);
  worker.submit(good, 1);
  std::unique_ptr<SparseCholesky> factor;
  REQUIRE(worker.take(factor, 1).ok);
  worker.submit(bad, 2);
  const BackgroundFactorizer::Taken taken = worker.take(factor, 2);
  CHECK(taken.found);
  CHECK_FALSE(taken.ok);
  REQUIRE(factor);
  CHECK(solve_residual(*factor, good) < 1e-10);  // the caller keeps the factor it had
}

TEST_CASE("reset drops what was queued for the old pattern", "[twin][solver]") {
  SmallSystem system;
  BackgroundFactorizer worker;
  worker.reset(system.matrix(1.0));
  worker.submit(system.matrix(1.0), 1);
  worker.reset(system.matrix(2.0));
  std::unique_ptr<SparseCholesky> factor;
  CHECK_FALSE(worker.take(factor, 1).found);
  worker.submit(system.matrix(2.0), 2);
  CHECK(worker.take(factor, 2).ok);
}

}  // namespace
}  // namespace twin
