#pragma once
// The reference sheet's surface: a tensor-product B-spline patch over the rectangle of material
// coordinates [0, W] x [0, H] (u across = weft, v up = warp, metres),
//   x(u, v) = sum_ij N_i(u) M_j(v) P_ij,
// with control points P (m, world frame, z up) numbered row-major, c = j * nu + i, stacked
// [x0 y0 z0 x1 ...]. Elements are the knot spans' rectangles; each carries a tensor Gauss rule
// (p + 1 points per direction by default) whose basis weights are computed once here, so the
// energies only combine control points.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "sim_hw/spline_shell/knot_vector.h"

namespace sim_hw::spline_shell {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using VecX = Eigen::VectorXd;

// Rows of the weight matrices: the derivative each row gives when applied to control points.
enum Derivative { kValue = 0, kU = 1, kV = 2, kUU = 3, kVV = 4, kUV = 5 };

// The weights of the control points that do not vanish at one material point: position and
// derivatives there are sum_k w(row, k) P_{controls[k]}.
struct PointWeights {
  std::vector<int> controls;
  Eigen::Matrix<double, 6, Eigen::Dynamic> w;
};

// A quadrature point of an element: its weights over the element's controls (in the element's
// order), its material point and its share of the sheet's area (m^2).
struct QuadraturePoint {
  Vec2 uv_m = Vec2::Zero();
  double area_m2 = 0;
  Eigen::Matrix<double, 6, Eigen::Dynamic> w;
};

class SplinePatch {
 public:
  // Throws std::invalid_argument when the degrees differ or the rule has fewer than p + 1 points.
  SplinePatch(KnotVector u, KnotVector v, int gauss_points = 0);

  const KnotVector& u() const { return u_; }
  const KnotVector& v() const { return v_; }
  int degree() const { return u_.degree(); }
  int nu() const { return u_.basis_count(); }
  int nv() const { return v_.basis_count(); }
  int control_count() const { return nu() * nv(); }
  int control(int i, int j) const { return j * nu() + i; }
  double width_m() const { return u_.length_m(); }
  double height_m() const { return v_.length_m(); }

  int element_count() const { return u_.element_count() * v_.element_count(); }
  // The element's (p + 1)^2 controls, k = kv (p + 1) + ku for N_{fu+ku} M_{fv+kv}, fu and fv the
  // first basis functions of its span in u and v.
  const std::vector<int>& element_controls(int element) const { return controls_[element]; }
  const std::vector<QuadraturePoint>& element_points(int element) const { return points_[element]; }
  // The element holding a material point (points off the sheet: the nearest element).
  int element_at(const Vec2& uv_m) const;

  PointWeights weights_at(const Vec2& uv_m) const;
  Vec3 position(const VecX& x, const Vec2& uv_m) const;
  // Unit normal x_u x x_v / |x_u x x_v|.
  Vec3 normal(const VecX& x, const Vec2& uv_m) const;
  // The curvature tensor's material components (x_uu . n, x_vv . n, x_uv . n) (1/m).
  Vec3 second_form(const VecX& x, const Vec2& uv_m) const;

  // The flat sheet in the plane z = 0 with x, y = u, v (controls at the Greville abscissae,
  // exact for a linear map).
  VecX flat_positions() const;
  // The spline interpolating a shape at the Greville abscissae (exact when the shape is in the
  // space; the patch tests and the carrying of shapes between patches use it).
  VecX interpolate(const std::function<Vec3(const Vec2&)>& shape) const;

 private:
  // A quadrature point of `element` at uv_m (inside it) standing for area_m2 of the sheet.
  QuadraturePoint point_in(int element, const Vec2& uv_m, double area_m2) const;

  KnotVector u_, v_;
  std::vector<std::vector<int>> controls_;
  std::vector<std::vector<QuadraturePoint>> points_;
};

// The control points of `coarse`'s surface on a patch whose knot vectors refine its own (exact
// knot insertion, knot_vector.h's prolongation in each direction).
VecX refine_controls(const SplinePatch& coarse, const VecX& x, const SplinePatch& fine);

}  // namespace sim_hw::spline_shell
