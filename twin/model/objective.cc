#include "twin/model/objective.h"

namespace twin {

double Objective::evaluate(const VecX& x, VecX* grad, HessianPattern* hess,
                           HessianMode mode) const {
  if (grad) grad->setZero(x.size());
  if (hess) hess->set_zero();
  double energy = 0.0;
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    const HessianTarget target{hess, static_cast<int>(t)};
    energy += terms_[t]->evaluate(x, grad, hess ? &target : nullptr, mode);
  }
  return energy;
}

std::vector<TermStencil> Objective::stencils() const {
  std::vector<TermStencil> stencils;
  for (const EnergyTerm* term : terms_) stencils.push_back({term->arity(), &term->element_vertices()});
  return stencils;
}

}  // namespace twin
