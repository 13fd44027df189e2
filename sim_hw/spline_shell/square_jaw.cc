#include "sim_hw/spline_shell/square_jaw.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "sim_hw/real_sheet/grid.h"

namespace sim_hw::spline_shell {

SquareJaw square_jaw(const std::string& id, const Vec2& m, double grip_radius_m, double width_m, double height_m) {
  if (!(grip_radius_m > 0) || !std::isfinite(grip_radius_m)) {
    throw std::invalid_argument(fmt::format("spline shell: jaw {} has grip radius {} m (expected positive)", id, grip_radius_m));
  }
  if (!(m.x() >= 0 && m.x() <= width_m && m.y() >= 0 && m.y() <= height_m)) {
    throw std::invalid_argument(fmt::format("spline shell: jaw {} at ({}, {}) m is off the {} x {} m sheet", id, m.x(),
                                            m.y(), width_m, height_m));
  }
  return SquareJaw{id, m, grip_radius_m * std::sqrt(std::numbers::pi) / 2.0};
}

std::pair<double, double> pad_interval(const SquareJaw& jaw, int axis, double length_m) {
  const double c = jaw.material_point_m[axis];
  return {std::max(0.0, c - jaw.half_side_m), std::min(length_m, c + jaw.half_side_m)};
}

double distance_to_pad_m(const SquareJaw& jaw, const Vec2& uv_m) {
  const Vec2 outside = ((uv_m - jaw.material_point_m).cwiseAbs().array() - jaw.half_side_m).cwiseMax(0.0);
  return outside.norm();
}

KnotVector jaw_knots(int degree, double length_m, int axis, const std::vector<SquareJaw>& jaws, double span_m,
                     double fine_span_m, double extension_m) {
  std::vector<real_sheet::GridAttractor> attractors;
  std::vector<double> edges, rings;
  const auto inside = [&](double e) { return e > 0 && e < length_m; };
  for (const SquareJaw& j : jaws) {
    const auto [lo, hi] = pad_interval(j, axis, length_m);
    for (double e : {lo, hi}) {
      if (inside(e)) edges.push_back(e);
      attractors.push_back({e, fine_span_m, 0.0});
    }
    if (extension_m > 0) {
      for (double e : {lo - extension_m, hi + extension_m}) {
        if (inside(e)) rings.push_back(e), attractors.push_back({e, fine_span_m, 0.0});
      }
    }
  }
  const auto distinct = [&](std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end(), [&](double a, double b) { return b - a < 1e-9 * length_m; }), v.end());
  };
  distinct(edges);
  // A ring's edge on a pad's edge (two jaws side by side) is that pad edge.
  std::erase_if(rings, [&](double r) {
    return std::any_of(edges.begin(), edges.end(), [&](double e) { return std::abs(r - e) < 1e-9 * length_m; });
  });
  distinct(rings);
  // The graded lines, less those too near an edge (a sliver of an element), plus the edges.
  std::vector<double> lines = real_sheet::graded_lines(length_m, span_m, attractors, 1.3);
  std::vector<double> breaks;
  for (double x : lines) {
    const auto near = [&](const std::vector<double>& v) {
      return std::any_of(v.begin(), v.end(), [&](double e) { return std::abs(x - e) < 0.4 * fine_span_m; });
    };
    if ((!near(edges) && !near(rings)) || x == 0.0 || x == length_m) breaks.push_back(x);
  }
  breaks.insert(breaks.end(), edges.begin(), edges.end());
  breaks.insert(breaks.end(), rings.begin(), rings.end());
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end(), [&](double a, double b) { return b - a < 1e-9 * length_m; }),
               breaks.end());
  std::vector<int> multiplicity(breaks.size(), 1);
  for (std::size_t k = 0; k < breaks.size(); ++k) {
    if (std::binary_search(edges.begin(), edges.end(), breaks[k])) multiplicity[k] = std::max(1, degree - 1);
  }
  return KnotVector(degree, breaks, multiplicity);
}

KnotVector refined(const KnotVector& k) {
  std::vector<double> breaks;
  std::vector<int> multiplicity;
  for (std::size_t i = 0; i + 1 < k.breaks().size(); ++i) {
    breaks.push_back(k.breaks()[i]);
    multiplicity.push_back(k.multiplicities()[i]);
    breaks.push_back(0.5 * (k.breaks()[i] + k.breaks()[i + 1]));
    multiplicity.push_back(1);
  }
  breaks.push_back(k.breaks().back());
  multiplicity.push_back(k.multiplicities().back());
  return KnotVector(k.degree(), breaks, multiplicity);
}

std::vector<int> held_controls(const SplinePatch& patch, const SquareJaw& jaw) {
  const auto [u0, u1] = pad_interval(jaw, 0, patch.width_m());
  const auto [v0, v1] = pad_interval(jaw, 1, patch.height_m());
  const auto [i0, i1] = patch.u().basis_meeting(u0, u1);
  const auto [j0, j1] = patch.v().basis_meeting(v0, v1);
  std::vector<int> controls;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) controls.push_back(patch.control(i, j));
  }
  std::sort(controls.begin(), controls.end());
  return controls;
}

void place_held_controls(const SplinePatch& patch, const SquareJaw& jaw, const std::vector<int>& controls,
                         const Vec3& centre_m, const Eigen::Matrix3d& rotation, VecX& x) {
  const std::vector<double> gu = patch.u().greville(), gv = patch.v().greville();
  for (int c : controls) {
    const int i = c % patch.nu(), j = c / patch.nu();
    const Vec3 d(gu[i] - jaw.material_point_m.x(), gv[j] - jaw.material_point_m.y(), 0.0);
    x.segment<3>(3 * c) = centre_m + rotation * d;
  }
}

}  // namespace sim_hw::spline_shell
