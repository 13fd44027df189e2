#pragma once
// The membrane energy of membrane_energy.h at one integration point of an element of N nodes.
//
// At the point the shape functions have gradients r_k = grad phi_k (row k of r, 1/m, in
// material coordinates); the weft and warp vectors are U = sum_k r_uk x_k, V = sum_k r_vk x_k,
// the Green-Lagrange strain eps = ((U.U - 1)/2, (V.V - 1)/2, U.V), the energy w 1/2 eps^T C eps
// with w the point's share of the rest area (m^2). The linear triangle is N = 3 with one point
// (its r constant); the quadratic triangle (quadratic_membrane.h) N = 6 with three.

#include <Eigen/Eigenvalues>

#include "twin/base/types.h"

namespace twin {

// Energy (J) at one point; ADDS its gradient (N) and Hessian (N/m) into *grad and *hess when
// non-null. DOF order: node k's (x, y, z) at 3k.
template <int N>
double add_membrane_point_energy(const Eigen::Matrix<double, N, 2>& r, double weight_m2, const Mat3& c,
                                 const Eigen::Matrix<double, 3 * N, 1>& xe,
                                 Eigen::Matrix<double, 3 * N, 1>* grad,
                                 Eigen::Matrix<double, 3 * N, 3 * N>* hess, HessianMode mode) {
  Vec3 u = Vec3::Zero(), v = Vec3::Zero();
  for (int k = 0; k < N; ++k) {
    u += r(k, 0) * xe.template segment<3>(3 * k);
    v += r(k, 1) * xe.template segment<3>(3 * k);
  }
  const Vec3 eps(0.5 * (u.squaredNorm() - 1.0), 0.5 * (v.squaredNorm() - 1.0), u.dot(v));
  const Vec3 sigma = c * eps;  // N/m
  if (grad || hess) {
    Eigen::Matrix<double, 3, 3 * N> j;  // d eps / d xe
    for (int k = 0; k < N; ++k) {
      j.template block<1, 3>(0, 3 * k) = r(k, 0) * u.transpose();
      j.template block<1, 3>(1, 3 * k) = r(k, 1) * v.transpose();
      j.template block<1, 3>(2, 3 * k) = (r(k, 0) * v + r(k, 1) * u).transpose();
    }
    if (grad) *grad += weight_m2 * j.transpose() * sigma;
    if (hess) {
      *hess += weight_m2 * j.transpose() * c * j;
      Mat2 stress;
      stress << sigma(0), sigma(2), sigma(2), sigma(1);
      if (mode == HessianMode::kProjected) {
        // Compressive principal stress gives negative geometric stiffness (buckling); dropping
        // it keeps the Hessian positive semi-definite.
        Eigen::SelfAdjointEigenSolver<Mat2> eig(stress);
        const Vec2 clamped = eig.eigenvalues().cwiseMax(0.0);
        stress = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
      }
      const Eigen::Matrix<double, N, N> geometric = weight_m2 * r * stress * r.transpose();
      for (int k = 0; k < N; ++k) {
        for (int l = 0; l < N; ++l) hess->template block<3, 3>(3 * k, 3 * l).diagonal().array() += geometric(k, l);
      }
    }
  }
  return 0.5 * weight_m2 * eps.dot(sigma);
}

}  // namespace twin
