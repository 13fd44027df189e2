#pragma once
// Common numeric types of the twin. Positions of a mesh with n vertices are stacked as one
// 3n vector [x0 y0 z0 x1 y1 z1 ...] in metres, world frame, z up.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace twin {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;

// Standard gravity (m/s^2).
inline constexpr double kStandardGravity = 9.80665;

// Position of vertex i in a stacked 3n vector.
inline auto vertex(const VecX& x, int i) { return x.segment<3>(3 * i); }
inline auto vertex(VecX& x, int i) { return x.segment<3>(3 * i); }

}  // namespace twin

namespace twin {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

// How an energy fills its Hessian.
//   kExact: the true second derivative (may be indefinite: compressed membranes, bent hinges).
//   kProjected: a positive semi-definite approximation per element (compressive membrane
//     stress dropped from the geometric stiffness; hinge bending by Gauss-Newton). Used far from
//     equilibrium and in dynamics, where it makes every Newton direction a descent direction.
enum class HessianMode { kExact, kProjected };

}  // namespace twin
