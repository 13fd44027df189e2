#include "twin/model/inertia_term.h"

#include <numeric>

namespace twin {

InertiaTerm::InertiaTerm(std::vector<double> vertex_masses_kg, double mass_damping_1_s)
    : masses_(std::move(vertex_masses_kg)), alpha_(mass_damping_1_s) {
  std::vector<int> vertices(masses_.size());
  std::iota(vertices.begin(), vertices.end(), 0);
  set_elements(std::move(vertices), static_cast<int>(masses_.size()));
}

void InertiaTerm::set_step(const VecX& x0, const VecX& v0, double dt_s) {
  x0_ = x0;
  predicted_ = x0 + dt_s * v0;
  dt_ = dt_s;
}

double InertiaTerm::element_energy(int i, const ElementVector& xe, ElementVector* g,
                                   ElementMatrix* h, HessianMode) const {
  const double k_inertia = masses_[i] / (dt_ * dt_);  // N/m
  const double k_damping = alpha_ * masses_[i] / dt_;  // N/m
  const Vec3 a = xe - predicted_.segment<3>(3 * i);
  const Vec3 b = xe - x0_.segment<3>(3 * i);
  if (g) *g = k_inertia * a + k_damping * b;
  if (h) *h = (k_inertia + k_damping) * Mat3::Identity();
  return 0.5 * (k_inertia * a.squaredNorm() + k_damping * b.squaredNorm());
}

}  // namespace twin
