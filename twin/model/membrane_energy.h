#pragma once
// Tensile and shear energy of one triangle, after Volino, Magnenat-Thalmann and Faure,
// "A simple approach to nonlinear tensile stiffness for accurate cloth simulation", ACM TOG 2009,
// as summarised in the prepreg twin paper, section 3.1.
//
// Rest state: the triangle in material coordinates (u, v). With the barycentric weights
// r_k = grad phi_k (1/m), the weft and warp vectors of the deformed triangle are
//   U = sum_k r_uk x_k,   V = sum_k r_vk x_k                       (paper Eq. 1)
// and the Green-Lagrange strain is eps = (eps_uu, eps_vv, gamma_uv) with
//   eps_uu = (U.U - 1)/2,  eps_vv = (V.V - 1)/2,  gamma_uv = U.V    (paper Eqs. 3-5)
// Energy: A0 * 1/2 eps^T C eps (J), C in N/m (Material::membrane_stiffness), stress sigma = C eps.
// Gradient (paper Eq. 7): A0 J^T sigma with J = d eps / d x (3 x 9).
// Hessian (paper Eq. 8): A0 (J^T C J + (R Sigma R^T) (x) I3), with Sigma = [[s_uu, s_uv],
// [s_uv, s_vv]] and R the 3 x 2 matrix of the r_k; the second part is the geometric stiffness.
// DOF order of the 9-vectors: (x_a, x_b, x_c), each (x, y, z).

#include <array>

#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

struct MembraneElement {
  std::array<int, 3> v{};                 // vertex ids a, b, c
  Eigen::Matrix<double, 3, 2> r;          // row k: (r_uk, r_vk), 1/m
  double rest_area_m2 = 0.0;
};

MembraneElement make_membrane_element(const SheetMesh& mesh, int triangle);

using StrainJacobian = Eigen::Matrix<double, 3, 9>;

// Strain (eps_uu, eps_vv, gamma_uv) at element positions xe (m), and d eps / d xe if requested.
Vec3 membrane_strain(const MembraneElement& e, const Vec9& xe, StrainJacobian* jacobian);

// Elastic energy (J). Writes (not adds) the gradient (N) and Hessian (N/m) when non-null.
double membrane_energy(const MembraneElement& e, const Mat3& stiffness_N_m, const Vec9& xe,
                       Vec9* grad, Mat9* hess, HessianMode mode);

}  // namespace twin
