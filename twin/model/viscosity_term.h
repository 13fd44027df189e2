#pragma once
// Strain-rate viscosity of the membrane (paper section 3.1: sigma = C eps + C' d(eps)/dt, and
// the damping Jacobian of Eq. 9). With C' = diag(eta_t, eta_t, eta_s) (N*s/m) and the strain
// Jacobian J0 = d eps / dx frozen at the start of a step of length dt, the viscous force
// -A0 J0^T C' J0 v with v = (x - x0)/dt derives from the dissipation potential
//   R(x) = A0 / (2 dt) (x - x0)^T J0^T C' J0 (x - x0)      (J)
// which the backward-Euler step minimises along with the other terms. R >= 0, so viscosity
// only ever removes energy.

#include "twin/model/energy_term.h"
#include "twin/model/membrane_energy.h"

namespace twin {

class ViscosityTerm final : public ElementTerm<3> {
 public:
  ViscosityTerm(const std::vector<MembraneElement>& elements, int vertex_count,
                double tensile_viscosity_Ns_m, double shear_viscosity_Ns_m);
  std::string_view name() const override { return "viscosity"; }
  void set_viscosity(double tensile_viscosity_Ns_m, double shear_viscosity_Ns_m);
  void set_step(const VecX& x0, double dt_s);
  bool active() const { return viscosity_.maxCoeff() > 0.0; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override;

 private:
  std::vector<MembraneElement> elements_;
  Vec3 viscosity_;
  std::vector<Mat9> damping_;  // A0 J0^T C' J0 per element (N*s/m)
  VecX x0_;
  double dt_ = 0.0;
};

}  // namespace twin
