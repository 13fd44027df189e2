#pragma once
// A sum of energy terms over the stacked positions x (3n, m).

#include <vector>

#include "twin/model/energy_term.h"

namespace twin {

class Objective {
 public:
  explicit Objective(std::vector<const EnergyTerm*> terms) : terms_(std::move(terms)) {}
  // Energy (J); gradient (3n, N) written (zeroed first) when non-null; Hessian added into the
  // pattern (zeroed first) when non-null. The pattern must have been built from stencils().
  double evaluate(const VecX& x, VecX* grad, HessianPattern* hess, HessianMode mode) const;
  std::vector<TermStencil> stencils() const;
  const std::vector<const EnergyTerm*>& terms() const { return terms_; }

 private:
  std::vector<const EnergyTerm*> terms_;
};

}  // namespace twin
