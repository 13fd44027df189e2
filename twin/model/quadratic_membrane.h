#pragma once
// Tensile and shear energy on quadratic (six-node) triangles: the membrane law of
// membrane_energy.h with positions interpolated quadratically over a triangle from its corners
// and edge midpoints, integrated with the three-point rule (exact for the stiffness of a small
// strain, whose displacement gradient is linear over the element).
//
// Why: a linear (constant-strain) triangle can bend without stretching only along its edges, so
// a fold across a mesh of them stretches it, and the fold comes out stiffer than the material
// (membrane locking; the stiffer the membrane against the bending, the worse). A quadratic
// triangle bends within itself. The six nodes are the vertices of a mesh refined uniformly once
// (SheetMesh::quadratic_patches): the same vertices as a linear mesh of four times the
// triangles, with the bending and the masses still on those small triangles.
//
// Node order of the 18-vectors: corners a, b, c, then the midpoints of ab, bc, ca, each (x, y, z).

#include <array>

#include "twin/model/energy_term.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

struct QuadraticMembraneElement {
  std::array<int, 6> v{};                          // a, b, c, mid ab, mid bc, mid ca
  std::array<Eigen::Matrix<double, 6, 2>, 3> r;    // shape-function gradients (1/m) per point
  double rest_area_m2 = 0.0;                        // the whole (parent) triangle's
};

// The element of mesh.quadratic_patches[patch]. Throws std::invalid_argument when the patch's
// midpoints are not the midpoints of its corners in material coordinates.
QuadraticMembraneElement make_quadratic_membrane_element(const SheetMesh& mesh, int patch);

using Vec18 = Eigen::Matrix<double, 18, 1>;
using Mat18 = Eigen::Matrix<double, 18, 18>;

// Elastic energy (J). Writes (not adds) the gradient (N) and Hessian (N/m) when non-null.
double quadratic_membrane_energy(const QuadraticMembraneElement& e, const Mat3& stiffness_N_m, const Vec18& xe,
                                 Vec18* grad, Mat18* hess, HessianMode mode);

// The sheet's membrane energy summed over the quadratic patches.
class QuadraticMembraneTerm final : public ElementTerm<6> {
 public:
  // Throws std::invalid_argument when the mesh has no quadratic patches.
  QuadraticMembraneTerm(const SheetMesh& mesh, const Mat3& stiffness_N_m);
  std::string_view name() const override { return "membrane (quadratic)"; }
  void set_stiffness(const Mat3& stiffness_N_m) { stiffness_ = stiffness_N_m; }

 protected:
  double element_energy(int e, const ElementVector& xe, ElementVector* g, ElementMatrix* h,
                        HessianMode mode) const override {
    return quadratic_membrane_energy(elements_[e], stiffness_, xe, g, h, mode);
  }

 private:
  std::vector<QuadraticMembraneElement> elements_;
  Mat3 stiffness_;
};

}  // namespace twin
