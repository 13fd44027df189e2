#include "twin/model/bending_term.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "twin/model/bending_stiffening.h"

namespace twin {

BendingTerm::BendingTerm(const SheetMesh& mesh, double rigidity_u_Nm, double rigidity_v_Nm)
    : hinges_(build_hinges(mesh)),
      calibration_(mesh, hinges_),
      curvature_map_(mesh, hinges_),
      stiffening_length_m_(stiffening_lengths(curvature_map_, calibration_)) {
  std::vector<int> vertices;
  vertices.reserve(4 * hinges_.size());
  elements_.resize(hinges_.size());
  for (std::size_t e = 0; e < hinges_.size(); ++e) {
    elements_[e].v = hinges_[e].v;
    vertices.insert(vertices.end(), hinges_[e].v.begin(), hinges_[e].v.end());
  }
  set_elements(std::move(vertices), mesh.vertex_count());
  set_rigidity(rigidity_u_Nm, rigidity_v_Nm);
}

void BendingTerm::set_rigidity(double rigidity_u_Nm, double rigidity_v_Nm) {
  const std::vector<double> k = calibration_.hinge_stiffnesses(rigidity_u_Nm, rigidity_v_Nm);
  for (std::size_t e = 0; e < elements_.size(); ++e) elements_[e].stiffness_Nm = k[e];
}

void BendingTerm::set_rest_angles(const std::vector<double>& angles_rad) {
  if (angles_rad.size() != elements_.size()) {
    throw std::invalid_argument("bending: " + std::to_string(angles_rad.size()) +
                                " rest angles given for " + std::to_string(elements_.size()) +
                                " hinges");
  }
  for (std::size_t e = 0; e < elements_.size(); ++e) elements_[e].rest_angle_rad = angles_rad[e];
  rest_from_curvature_ = false;
}

void BendingTerm::set_rest_curvature(const CurvatureTensor& k) {
  if (rest_from_curvature_ && k == rest_curvature_) return;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    elements_[e].rest_angle_rad = curvature_map_.rest_angle(static_cast<int>(e), k);
  }
  rest_curvature_ = k;
  rest_from_curvature_ = true;
}

void BendingTerm::set_stiffening(double beta_m2) {
  if (!(std::isfinite(beta_m2) && beta_m2 >= 0.0)) {
    throw std::invalid_argument("bending: stiffening beta must be a finite number >= 0 (m^2), "
                                "got " + std::to_string(beta_m2));
  }
  if (beta_m2 == beta_m2_) return;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const double d = stiffening_length_m_[e];
    elements_[e].quartic_per_rad2 = beta_m2 / (2.0 * d * d);
  }
  beta_m2_ = beta_m2;
}

}  // namespace twin
