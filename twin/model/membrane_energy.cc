#include "twin/model/membrane_energy.h"

#include "twin/model/membrane_point.h"

namespace twin {

MembraneElement make_membrane_element(const SheetMesh& mesh, int triangle) {
  MembraneElement e;
  e.v = mesh.triangles[triangle];
  const Vec2& pa = mesh.rest_uv[e.v[0]];
  const Vec2& pb = mesh.rest_uv[e.v[1]];
  const Vec2& pc = mesh.rest_uv[e.v[2]];
  // Columns are rest edges; phi_b and phi_c have gradients given by the rows of the inverse,
  // phi_a = 1 - phi_b - phi_c. (Equivalent to the paper's r = d^-1 (v_b - v_c), ...)
  Mat2 edges;
  edges.col(0) = pb - pa;
  edges.col(1) = pc - pa;
  const Mat2 inv = edges.inverse();
  e.r.row(1) = inv.row(0);
  e.r.row(2) = inv.row(1);
  e.r.row(0) = -inv.row(0) - inv.row(1);
  e.rest_area_m2 = 0.5 * edges.determinant();
  return e;
}

Vec3 membrane_strain(const MembraneElement& e, const Vec9& xe, StrainJacobian* jacobian) {
  Vec3 u = Vec3::Zero(), v = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    u += e.r(k, 0) * xe.segment<3>(3 * k);
    v += e.r(k, 1) * xe.segment<3>(3 * k);
  }
  if (jacobian) {
    for (int k = 0; k < 3; ++k) {
      jacobian->block<1, 3>(0, 3 * k) = e.r(k, 0) * u.transpose();
      jacobian->block<1, 3>(1, 3 * k) = e.r(k, 1) * v.transpose();
      jacobian->block<1, 3>(2, 3 * k) = (e.r(k, 0) * v + e.r(k, 1) * u).transpose();
    }
  }
  return Vec3(0.5 * (u.squaredNorm() - 1.0), 0.5 * (v.squaredNorm() - 1.0), u.dot(v));
}

double membrane_energy(const MembraneElement& e, const Mat3& c, const Vec9& xe, Vec9* grad,
                       Mat9* hess, HessianMode mode) {
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  const Eigen::Matrix<double, 3, 2>& r = e.r;
  return add_membrane_point_energy<3>(r, e.rest_area_m2, c, xe, grad, hess, mode);
}

}  // namespace twin
