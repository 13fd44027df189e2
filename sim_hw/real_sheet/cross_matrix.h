#pragma once
// The matrix [v]x with [v]x * w = v x w: the derivative of a cross product with respect to its
// second factor, shared by the bending stencil and the jaw pads' moments.
#include <Eigen/Core>

namespace sim_hw::real_sheet {

inline Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace sim_hw::real_sheet
