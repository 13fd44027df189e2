#include "twin/model/gravity_term.h"

#include <numeric>

namespace twin {

GravityTerm::GravityTerm(std::vector<double> vertex_masses_kg, const Vec3& gravity_m_s2)
    : masses_(std::move(vertex_masses_kg)), vertices_(masses_.size()), gravity_(gravity_m_s2) {
  std::iota(vertices_.begin(), vertices_.end(), 0);
}

double GravityTerm::evaluate(const VecX& x, VecX* grad, const HessianTarget*, HessianMode) const {
  double energy = 0.0;
  const int n = static_cast<int>(masses_.size());
  for (int i = 0; i < n; ++i) {
    energy -= masses_[i] * gravity_.dot(x.segment<3>(3 * i));
    if (grad) grad->segment<3>(3 * i) -= masses_[i] * gravity_;
  }
  return energy;
}

}  // namespace twin
