#pragma once
// Finite-difference check of one assembled energy term (every vertex free): its gradient and
// its Hessian as the solvers see them, through an Objective and a HessianPattern.

#include <memory>

#include "tests/support/finite_difference.h"
#include "twin/model/hessian_pattern.h"
#include "twin/model/objective.h"

namespace twin::testing {

inline DerivativeErrors term_derivative_errors(const EnergyTerm& term, const VecX& x, double step = 1e-7) {
  const Objective objective({&term});
  const DofMap dofs(std::vector<char>(x.size() / 3, 0));
  auto pattern = std::make_shared<HessianPattern>(dofs, objective.stencils());
  auto f = [&objective, pattern](const VecX& y, VecX* g, Eigen::MatrixXd* h) {
    const double e = objective.evaluate(y, g, h ? pattern.get() : nullptr, HessianMode::kExact);
    if (h) {
      const Eigen::MatrixXd upper(pattern->matrix());
      *h = upper.selfadjointView<Eigen::Upper>();
    }
    return e;
  };
  return finite_difference_errors(f, x, step);
}

}  // namespace twin::testing
