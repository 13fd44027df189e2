#pragma once
// Inertia and mass damping of one backward-Euler step of length dt (s), as an incremental
// potential (the step's positions minimise it together with the elastic energy):
//   E = sum_i m_i |x_i - xt_i|^2 / (2 dt^2) + alpha m_i |x_i - x0_i|^2 / (2 dt)     (J)
// with xt = x0 + dt v0 the inertial prediction, x0 and v0 the state at the start of the step,
// and alpha (1/s) the mass-proportional damping (force -alpha m v).

#include "twin/model/energy_term.h"

namespace twin {

class InertiaTerm final : public ElementTerm<1> {
 public:
  InertiaTerm(std::vector<double> vertex_masses_kg, double mass_damping_1_s);
  std::string_view name() const override { return "inertia"; }
  void set_step(const VecX& x0, const VecX& v0, double dt_s);
  void set_masses(std::vector<double> vertex_masses_kg) { masses_ = std::move(vertex_masses_kg); }
  void set_mass_damping(double mass_damping_1_s) { alpha_ = mass_damping_1_s; }

 protected:
  double element_energy(int i, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override;

 private:
  std::vector<double> masses_;
  double alpha_;
  VecX x0_, predicted_;
  double dt_ = 0.0;
};

}  // namespace twin
