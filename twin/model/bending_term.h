#pragma once
// The sheet's bending energy: hinge_bending.h summed over all interior edges, with stiffnesses
// from bending_calibration.h so the parameters are the plate rigidities D_u, D_v (N*m), rest
// angles from a rest curvature tensor (rest_curvature.h) and an optional stiffening
// (bending_stiffening.h).

#include "twin/model/bending_calibration.h"
#include "twin/model/energy_term.h"
#include "twin/model/hinge_bending.h"
#include "twin/model/rest_curvature.h"

namespace twin {

class BendingTerm final : public ElementTerm<4> {
 public:
  BendingTerm(const SheetMesh& mesh, double rigidity_u_Nm, double rigidity_v_Nm);
  std::string_view name() const override { return "bending"; }
  void set_rigidity(double rigidity_u_Nm, double rigidity_v_Nm);
  // Rest angles (rad), one per hinge; zero (flat) unless a rest curvature is modelled.
  void set_rest_angles(const std::vector<double>& angles_rad);
  // Rest angles of a sheet with rest curvature k (1/m, material frame). Does nothing when k is
  // the tensor already applied (identification sets the material thousands of times).
  void set_rest_curvature(const CurvatureTensor& k);
  // Bending stiffening beta (m^2, >= 0): M = D kappa (1 + beta kappa^2).
  void set_stiffening(double beta_m2);
  const std::vector<Hinge>& hinges() const { return hinges_; }
  const std::vector<HingeElement>& elements() const { return elements_; }
  const HingeCurvatureMap& curvature_map() const { return curvature_map_; }
  // d_e (m) per hinge: hinge angle per curvature for the stiffening (bending_stiffening.h).
  const std::vector<double>& stiffening_lengths_m() const { return stiffening_length_m_; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override {
    return hinge_bending_energy(elements_[e], xe, g, h, mode);
  }

 private:
  std::vector<Hinge> hinges_;
  BendingCalibration calibration_;
  HingeCurvatureMap curvature_map_;
  std::vector<double> stiffening_length_m_;
  std::vector<HingeElement> elements_;
  // The tensor the rest angles were made from; unset after set_rest_angles.
  bool rest_from_curvature_ = true;
  CurvatureTensor rest_curvature_;
  double beta_m2_ = 0.0;
};

}  // namespace twin
