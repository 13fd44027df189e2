#include "twin/model/plate_bending.h"

#include <Eigen/Eigenvalues>

#include "twin/model/dihedral_angle.h"

namespace twin {

std::array<int, 4> plate_hinge_local_vertices(int k) {
  return {(k + 1) % 3, (k + 2) % 3, k, 3 + k};
}

double plate_bending_energy(const PlateElement& e, const Vec18& x, Vec18* grad, Mat18* hess,
                            HessianMode mode) {
  const int m = e.hinge_count;
  const bool exact = hess && mode == HessianMode::kExact;
  std::array<Vec12, 3> g;
  std::array<Mat12, 3> h;
  std::array<std::array<int, 4>, 3> local;
  Vec3 d = Vec3::Zero();
  for (int j = 0; j < m; ++j) {
    local[j] = plate_hinge_local_vertices(e.edge[j]);
    Vec12 xh;
    for (int k = 0; k < 4; ++k) xh.segment<3>(3 * k) = x.segment<3>(3 * local[j][k]);
    d(j) = dihedral_angle(xh, (grad || hess) ? &g[j] : nullptr, exact ? &h[j] : nullptr) -
           e.rest_angle_rad(j);
  }
  const Vec3 qd = e.q * d, rd = e.r * d;
  const double q = d.dot(qd), p = d.dot(rd), beta = e.stiffening_m2;
  const double energy = 0.5 * q * (1.0 + 0.5 * beta * p);
  if (!grad && !hess) return energy;

  // psi_j and psi_jk (derivatives in d), see the header.
  const Vec3 dpsi = qd * (1.0 + 0.5 * beta * p) + 0.5 * beta * q * rd;
  Mat3 ddpsi = e.q * (1.0 + 0.5 * beta * p);
  if (beta != 0.0) ddpsi += 0.5 * beta * q * e.r + beta * (qd * rd.transpose() + rd * qd.transpose());

  // Angle gradients on the element's 18 DOFs.
  std::array<Vec18, 3> G;
  for (int j = 0; j < m; ++j) {
    G[j].setZero();
    for (int k = 0; k < 4; ++k) G[j].segment<3>(3 * local[j][k]) = g[j].segment<3>(3 * k);
  }
  if (grad) {
    grad->setZero();
    for (int j = 0; j < m; ++j) *grad += dpsi(j) * G[j];
  }
  if (hess) {
    if (!exact && beta != 0.0) {
      // Clip psi_jk's negative eigenvalues (stiffening can make it indefinite far out).
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(ddpsi.topLeftCorner(m, m));
      const Eigen::VectorXd lambda = eig.eigenvalues().cwiseMax(0.0);
      ddpsi.topLeftCorner(m, m) = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
    }
    hess->setZero();
    for (int j = 0; j < m; ++j) {
      for (int k = 0; k < m; ++k) hess->noalias() += ddpsi(j, k) * G[j] * G[k].transpose();
    }
    if (exact) {
      for (int j = 0; j < m; ++j) {
        for (int a = 0; a < 4; ++a) {
          for (int b = 0; b < 4; ++b) {
            hess->block<3, 3>(3 * local[j][a], 3 * local[j][b]) += dpsi(j) * h[j].block<3, 3>(3 * a, 3 * b);
          }
        }
      }
    }
  }
  return energy;
}

}  // namespace twin
