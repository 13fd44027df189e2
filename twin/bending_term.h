#pragma once
// The sheet's bending energy: hinge_bending.h summed over all interior edges, with stiffnesses
// from bending_calibration.h so the parameters are the plate rigidities D_u, D_v (N*m).

#include "twin/bending_calibration.h"
#include "twin/energy_term.h"
#include "twin/hinge_bending.h"

namespace twin {

class BendingTerm final : public ElementTerm<4> {
 public:
  BendingTerm(const SheetMesh& mesh, double rigidity_u_Nm, double rigidity_v_Nm);
  std::string_view name() const override { return "bending"; }
  void set_rigidity(double rigidity_u_Nm, double rigidity_v_Nm);
  // Rest angles (rad), one per hinge; zero (flat) unless a rest curvature is modelled.
  void set_rest_angles(const std::vector<double>& angles_rad);
  const std::vector<Hinge>& hinges() const { return hinges_; }
  const std::vector<HingeElement>& elements() const { return elements_; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override {
    return hinge_bending_energy(elements_[e], xe, g, h, mode);
  }

 private:
  std::vector<Hinge> hinges_;
  BendingCalibration calibration_;
  std::vector<HingeElement> elements_;
};

}  // namespace twin
