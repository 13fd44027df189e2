#pragma once
// A clamp's jaws on the reference sheet: a square pad of the grip disc's area (half side
// a = r sqrt(pi) / 2), its sides along the material axes, centred on the clamp's material point
// (clipped to the sheet at an edge). The knots run through the pad's edges with multiplicity
// p - 1, so the spline is C1 there and its curvature may jump where the ply leaves the jaws, as
// a clamped plate's does; every control whose basis function reaches into the pad is then held
// at the rigid motion of the flat sheet the jaw's pose prescribes (the flat sheet's controls
// sit at the Greville abscissae, which reproduce an affine map exactly), so the surface is that
// rigid motion on the whole pad and nowhere else: the hold is exact at every refinement.
// A disc cannot be held that way by a tensor-product spline: a penalty over the disc, or on its
// rim with the slope, locks every element the circle cuts (a polynomial held rigid on part of
// an element is rigid on all of it), and the hold then converges at first order only (measured
// on the two-jaw test of tests/sim_hw/spline_shell: markers still moved 3.4 mm between 6.25 and
// 3.1 mm elements). The square of equal area is this model's form of the jaws; the difference
// from a disc is the jaws' shape, not the discretisation's error.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sim_hw/spline_shell/spline_patch.h"

namespace sim_hw::spline_shell {

struct SquareJaw {
  std::string id;
  Vec2 material_point_m = Vec2::Zero();
  double half_side_m = 0;
};

// The jaw of a clamp of grip radius r at a material point. Throws std::invalid_argument for a
// non-positive radius or a point off the sheet (width x height).
SquareJaw square_jaw(const std::string& id, const Vec2& material_point_m, double grip_radius_m, double width_m,
                     double height_m);

// The pad's interval along u (axis 0) or v (axis 1), clipped to [0, length].
std::pair<double, double> pad_interval(const SquareJaw& jaw, int axis, double length_m);

// The material distance (m) from uv to the jaw's pad, 0 inside it.
double distance_to_pad_m(const SquareJaw& jaw, const Vec2& uv_m);

// One direction's knots for a sheet of `length_m` held by `jaws`: spans of at most `span_m`,
// graded to `fine_span_m` around every pad edge (growing by 1.3 per span away from it), and the
// pad edges as knots of multiplicity p - 1; with wide jaws (extension_m > 0, jaw_grip.h) the
// ring's outer edges too, as simple knots graded alike. Bisecting every span (refined) keeps them.
KnotVector jaw_knots(int degree, double length_m, int axis, const std::vector<SquareJaw>& jaws, double span_m,
                     double fine_span_m, double extension_m = 0);
// Every span split in two: the next level of a refinement study (nested: knot insertion).
KnotVector refined(const KnotVector& knots);

// The controls the pad holds (sorted), and their positions for the jaw at pose (c, R): the rigid
// motion x = c + R (u - u_j, v - v_j, 0) of the flat sheet, at the controls' Greville points.
std::vector<int> held_controls(const SplinePatch& patch, const SquareJaw& jaw);
void place_held_controls(const SplinePatch& patch, const SquareJaw& jaw, const std::vector<int>& controls,
                         const Vec3& centre_m, const Eigen::Matrix3d& rotation, VecX& x);

}  // namespace sim_hw::spline_shell
