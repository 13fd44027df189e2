#include "twin/model/viscosity_term.h"

namespace twin {

ViscosityTerm::ViscosityTerm(const std::vector<MembraneElement>& elements, int vertex_count,
                             double tensile_viscosity_Ns_m, double shear_viscosity_Ns_m)
    : elements_(elements), damping_(elements.size(), Mat9::Zero()) {
  set_viscosity(tensile_viscosity_Ns_m, shear_viscosity_Ns_m);
  std::vector<int> vertices;
  vertices.reserve(3 * elements.size());
  for (const MembraneElement& e : elements) vertices.insert(vertices.end(), e.v.begin(), e.v.end());
  set_elements(std::move(vertices), vertex_count);
}

void ViscosityTerm::set_viscosity(double tensile_viscosity_Ns_m, double shear_viscosity_Ns_m) {
  viscosity_ = Vec3(tensile_viscosity_Ns_m, tensile_viscosity_Ns_m, shear_viscosity_Ns_m);
  // Turned off: no damping left over from an earlier step.
  if (!active()) std::fill(damping_.begin(), damping_.end(), Mat9::Zero());
}

void ViscosityTerm::set_step(const VecX& x0, double dt_s) {
  x0_ = x0;
  dt_ = dt_s;
  if (!active()) return;
  const int n = static_cast<int>(elements_.size());
#pragma omp parallel for schedule(static)
  for (int e = 0; e < n; ++e) {
    const MembraneElement& el = elements_[e];
    Vec9 xe;
    for (int k = 0; k < 3; ++k) xe.segment<3>(3 * k) = x0.segment<3>(3 * el.v[k]);
    StrainJacobian j;
    membrane_strain(el, xe, &j);
    damping_[e] = el.rest_area_m2 * j.transpose() * viscosity_.asDiagonal() * j;
  }
}

double ViscosityTerm::element_energy(int e, const ElementVector& xe, ElementVector* g,
                                     ElementMatrix* h, HessianMode) const {
  const MembraneElement& el = elements_[e];
  Vec9 dx;
  for (int k = 0; k < 3; ++k) dx.segment<3>(3 * k) = xe.segment<3>(3 * k) - x0_.segment<3>(3 * el.v[k]);
  const Vec9 f = damping_[e] * dx / dt_;
  if (g) *g = f;
  if (h) *h = damping_[e] / dt_;
  return 0.5 * dx.dot(f);
}

}  // namespace twin
