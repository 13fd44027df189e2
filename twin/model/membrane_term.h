#pragma once
// The sheet's tensile and shear energy: membrane_energy.h summed over all triangles.

#include "twin/model/energy_term.h"
#include "twin/model/membrane_energy.h"

namespace twin {

class MembraneTerm final : public ElementTerm<3> {
 public:
  MembraneTerm(const SheetMesh& mesh, const Mat3& stiffness_N_m);
  std::string_view name() const override { return "membrane"; }
  void set_stiffness(const Mat3& stiffness_N_m) { stiffness_ = stiffness_N_m; }
  const std::vector<MembraneElement>& elements() const { return elements_; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override {
    return membrane_energy(elements_[e], stiffness_, xe, g, h, mode);
  }

 private:
  std::vector<MembraneElement> elements_;
  Mat3 stiffness_;
};

}  // namespace twin
