#pragma once
// One direction of the reference sheet's spline space: an open (clamped) knot vector of degree p
// over breakpoints 0 = b_0 < b_1 < ... < b_m = L (metres of material coordinate). An interior
// breakpoint of multiplicity k leaves the basis C^(p-k) across it: simple knots (C^(p-1))
// everywhere but at a jaw's edges, where multiplicity p - 1 leaves C^1, the continuity a
// Kirchhoff-Love shell needs and the clamp's edge allows (the curvature jumps there). There are
// p + 1 + sum of interior multiplicities basis functions; the elements are the m knot spans.
// The basis and its derivatives come from Eigen's Splines module.

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace sim_hw::spline_shell {

class KnotVector {
 public:
  // Throws std::invalid_argument for a degree outside 2..4, fewer than two breakpoints,
  // breakpoints that are not finite and strictly increasing from 0, or multiplicities (one per
  // breakpoint, ends ignored; empty: all simple) outside 1..p - 1.
  KnotVector(int degree, std::vector<double> breaks_m, std::vector<int> multiplicities = {});

  int degree() const { return degree_; }
  int basis_count() const { return static_cast<int>(knots_.size()) - degree_ - 1; }
  int element_count() const { return static_cast<int>(breaks_.size()) - 1; }
  const std::vector<double>& breaks() const { return breaks_; }
  const std::vector<int>& multiplicities() const { return multiplicity_; }
  double length_m() const { return breaks_.back(); }
  const Eigen::Array<double, 1, Eigen::Dynamic>& knots() const { return knots_; }

  // The element (knot span) holding u; u outside [0, L] is clamped onto it.
  int element_at(double u_m) const;
  // The p + 1 basis functions that do not vanish on element e are first .. first + p, with
  // first = first_basis(e). values(r, k) is the r-th derivative (1/m^r) of basis function first + k at u.
  struct Values {
    int first = 0;
    Eigen::ArrayXXd values;
  };
  Values evaluate(double u_m, int derivatives) const;
  Values evaluate_in(int element, double u_m, int derivatives) const;
  int first_basis(int element) const { return first_[element]; }
  // The basis functions whose support meets the open interval (lo, hi).
  std::pair<int, int> basis_meeting(double lo_m, double hi_m) const;  // [first, last]

  // The Greville abscissae (knot averages), one per basis function: control points placed at them
  // reproduce linear functions exactly (the flat sheet).
  std::vector<double> greville() const;

 private:
  int degree_;
  std::vector<double> breaks_;
  std::vector<int> multiplicity_;
  std::vector<int> first_;
  Eigen::Array<double, 1, Eigen::Dynamic> knots_;
};

// The exact prolongation from a coarse to a finer space of the same degree whose breakpoints
// contain the coarse ones with at least their multiplicities (knot insertion): fine control values = T * coarse control values
// represent the same function. T (fine x coarse) is found by interpolating the coarse basis at
// the fine space's Greville abscissae (unisolvent by Schoenberg-Whitney), exact up to rounding.
// Throws std::invalid_argument when the degrees differ or the fine knots miss a coarse one.
Eigen::MatrixXd prolongation(const KnotVector& coarse, const KnotVector& fine);

// Graded breakpoints: sim_hw/real_sheet/grid.h's graded_lines (fine spans at the jaws and the
// folds, growing geometrically away from them).

// Gauss-Legendre points and weights on [a, b] (n points, exact for degree 2n - 1).
struct GaussRule {
  std::vector<double> points, weights;
};
GaussRule gauss_legendre(int n, double a, double b);

}  // namespace sim_hw::spline_shell
