#pragma once
// The sheet's bending energy as a plate: plate_bending.h summed over all triangles, with the
// material's full rigidity matrix D (N*m), an optional rest curvature (rest_curvature.h) and an
// optional isotropic stiffening. The alternative to BendingTerm (hinges), chosen by the
// material's bending_model.

#include <vector>

#include "twin/model/energy_term.h"
#include "twin/model/plate_bending.h"
#include "twin/model/rest_curvature.h"
#include "twin/mesh/sheet_mesh.h"

namespace twin {

class PlateBendingTerm final : public ElementTerm<6> {
 public:
  // `rigidity_Nm` is D on (K_uu, K_vv, 2 K_uv); throws std::invalid_argument unless it is
  // symmetric positive definite with D13 = D23 = 0, or for a degenerate rest hinge.
  PlateBendingTerm(const SheetMesh& mesh, const Mat3& rigidity_Nm);
  std::string_view name() const override { return "plate bending"; }
  void set_rigidity(const Mat3& rigidity_Nm);
  void set_rest_curvature(const CurvatureTensor& k);
  // beta (m^2, >= 0): M = D kappa (1 + beta |K|^2).
  void set_stiffening(double beta_m2);
  const Mat3& rigidity() const { return rigidity_; }

  // The curvature (K_uu, K_vv, K_uv) (1/m, material frame) that triangle `element` shows at x,
  // relative to its rest curvature: the least-energy tensor consistent with its hinge angles.
  Vec3 curvature(const VecX& x, int element) const;
  // Rest area (m^2) of the element's triangle, and its number of edges with a neighbour.
  double rest_area(int element) const { return area_m2_[element]; }
  int hinge_count(int element) const { return elements_[element].hinge_count; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override {
    return plate_bending_energy(elements_[e], xe, g, h, mode);
  }

 private:
  // A rows (rad per kappa, m) of element e's hinges.
  std::vector<Mat3> angle_per_curvature_;
  std::vector<Mat3> curvature_per_angle_;  // M (3 x m used)
  std::vector<double> area_m2_;
  std::vector<PlateElement> elements_;
  Mat3 rigidity_ = Mat3::Zero();
  CurvatureTensor rest_curvature_;  // the tensor the rest angles were made from
};

// D (N*m) of an orthotropic plate from its four rigidities.
Mat3 plate_rigidity_matrix(double d11_Nm, double d22_Nm, double d12_Nm, double d66_Nm);

}  // namespace twin
