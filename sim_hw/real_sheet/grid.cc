#include "sim_hw/real_sheet/grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::real_sheet {
namespace {

void check_lines(const std::vector<double>& lines, const char* axis) {
  if (lines.size() < 3 || lines.front() != 0.0) {
    throw std::invalid_argument(fmt::format("real sheet grid: {} lines must start at 0 and number at least 3", axis));
  }
  for (std::size_t k = 1; k < lines.size(); ++k) {
    if (!(lines[k] > lines[k - 1]) || !std::isfinite(lines[k])) {
      throw std::invalid_argument(fmt::format("real sheet grid: {} line {} at {} m does not increase", axis, k, lines[k]));
    }
  }
}

std::vector<double> uniform_lines(double length_m, double max_spacing_m) {
  const int n = std::max(3, static_cast<int>(std::ceil(length_m / max_spacing_m - 1e-9)) + 1);
  std::vector<double> lines(n);
  for (int k = 0; k < n; ++k) lines[k] = length_m * k / (n - 1);
  lines.back() = length_m;
  return lines;
}

int cell_index(const std::vector<double>& lines, double x) {
  const auto it = std::upper_bound(lines.begin(), lines.end(), x);
  const int i = static_cast<int>(it - lines.begin()) - 1;
  return std::clamp(i, 0, static_cast<int>(lines.size()) - 2);
}

}  // namespace

std::vector<double> graded_lines(double length_m, double max_spacing_m, const std::vector<GridAttractor>& attractors,
                                 double growth) {
  if (!(length_m > 0) || !(max_spacing_m > 0) || !(growth > 1.0)) {
    throw std::invalid_argument(fmt::format("real sheet grid: length {} m, spacing {} m, growth {} (expected positive, "
                                            "growth above 1)", length_m, max_spacing_m, growth));
  }
  // The wanted spacing at x: each attractor's, growing by (growth - 1) per metre of distance
  // beyond its reach (geometric growth per cell), capped at max_spacing.
  const auto spacing = [&](double x) {
    double h = max_spacing_m;
    for (const GridAttractor& a : attractors) {
      h = std::min(h, a.spacing_m + (growth - 1.0) * std::max(0.0, std::abs(x - a.at_m) - a.reach_m));
    }
    return h;
  };
  // Fixed lines: the ends, and each attractor's fine zone (a line through its centre and every
  // spacing within reach), dropping lines nearer than half the local spacing to one kept.
  std::vector<std::pair<double, int>> wanted = {{0.0, 0}, {length_m, 0}};  // (position, priority)
  for (const GridAttractor& a : attractors) {
    if (!(a.spacing_m > 0)) throw std::invalid_argument("real sheet grid: an attractor's spacing must be positive");
    const int m = static_cast<int>(std::floor(a.reach_m / a.spacing_m + 1e-9));
    for (int k = -m; k <= m; ++k) {
      const double x = a.at_m + k * a.spacing_m;
      if (x > 0 && x < length_m) wanted.push_back({x, k == 0 ? 1 : 2});
    }
  }
  std::sort(wanted.begin(), wanted.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  std::vector<double> fixed;
  for (const auto& [position, priority] : wanted) {
    const double x = position;  // a plain variable: clang 14 cannot capture a structured binding
    const bool clear = std::all_of(fixed.begin(), fixed.end(), [&](double f) { return std::abs(f - x) >= 0.5 * spacing(x); });
    if (clear || priority == 0) fixed.push_back(x);
  }
  std::sort(fixed.begin(), fixed.end());
  // Between fixed lines: n cells with equal steps of the integral of 1 / spacing.
  std::vector<double> lines = {0.0};
  for (std::size_t s = 0; s + 1 < fixed.size(); ++s) {
    const double a = fixed[s], b = fixed[s + 1];
    constexpr int kSamples = 400;
    std::vector<double> integral(kSamples + 1, 0.0);
    for (int k = 0; k < kSamples; ++k) {
      const double x = a + (b - a) * (k + 0.5) / kSamples;
      integral[k + 1] = integral[k] + (b - a) / kSamples / spacing(x);
    }
    const int n = std::max(1, static_cast<int>(std::lround(integral.back())));
    for (int c = 1; c < n; ++c) {
      const double target = integral.back() * c / n;
      const int k = static_cast<int>(std::lower_bound(integral.begin(), integral.end(), target) - integral.begin());
      const double f = (target - integral[k - 1]) / (integral[k] - integral[k - 1]);
      lines.push_back(a + (b - a) * (k - 1 + f) / kSamples);
    }
    lines.push_back(b);
  }
  lines.back() = length_m;
  return lines;
}

Grid graded_grid(double width_m, double height_m, const std::vector<JawSpot>& jaws, double max_spacing_m) {
  const double fine = 0.25 * max_spacing_m;
  std::vector<GridAttractor> u = {{0.0, fine, 0.0}, {width_m, fine, 0.0}}, v = {{0.0, fine, 0.0}, {height_m, fine, 0.0}};
  for (const JawSpot& j : jaws) {
    const double reach = 1.5 * std::max(j.radius_m, fine);
    u.push_back({j.material_point_m.x(), fine, reach});
    v.push_back({j.material_point_m.y(), fine, reach});
  }
  return Grid(graded_lines(width_m, max_spacing_m, u), graded_lines(height_m, max_spacing_m, v));
}

Grid::Grid(double width_m, double height_m, double max_spacing_m) {
  if (!(width_m > 0) || !(height_m > 0) || !(max_spacing_m > 0) || !std::isfinite(width_m) ||
      !std::isfinite(height_m) || !std::isfinite(max_spacing_m)) {
    throw std::invalid_argument(fmt::format("real sheet grid: sheet {} x {} m with spacing {} m (all must be positive)",
                                            width_m, height_m, max_spacing_m));
  }
  u_ = uniform_lines(width_m, max_spacing_m);
  v_ = uniform_lines(height_m, max_spacing_m);
}

Grid::Grid(std::vector<double> u_lines_m, std::vector<double> v_lines_m) : u_(std::move(u_lines_m)), v_(std::move(v_lines_m)) {
  check_lines(u_, "u");
  check_lines(v_, "v");
}

double Grid::max_spacing_m() const {
  double h = 0;
  for (int i = 0; i + 1 < nu(); ++i) h = std::max(h, du(i));
  for (int j = 0; j + 1 < nv(); ++j) h = std::max(h, dv(j));
  return h;
}

double Grid::min_spacing_m() const {
  double h = 1e300;
  for (int i = 0; i + 1 < nu(); ++i) h = std::min(h, du(i));
  for (int j = 0; j + 1 < nv(); ++j) h = std::min(h, dv(j));
  return h;
}

double Grid::node_area_m2(int node) const {
  const int i = node % nu(), j = node / nu();
  const double wu = 0.5 * ((i > 0 ? du(i - 1) : 0.0) + (i + 1 < nu() ? du(i) : 0.0));
  const double wv = 0.5 * ((j > 0 ? dv(j - 1) : 0.0) + (j + 1 < nv() ? dv(j) : 0.0));
  return wu * wv;
}

VecX Grid::flat_positions() const {
  VecX x = VecX::Zero(3 * node_count());
  for (int n = 0; n < node_count(); ++n) x.segment<2>(3 * n) = rest_uv(n);
  return x;
}

Grid::Location Grid::locate(const Vec2& uv_m) const {
  const double u = std::clamp(uv_m.x(), 0.0, width_m()), v = std::clamp(uv_m.y(), 0.0, height_m());
  const int i = cell_index(u_, u), j = cell_index(v_, v);
  const double a = (u - u_[i]) / du(i), b = (v - v_[j]) / dv(j);
  Location at;
  at.nodes = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
  at.weights = {(1 - a) * (1 - b), a * (1 - b), a * b, (1 - a) * b};
  return at;
}

Vec3 Grid::position(const VecX& x, const Location& at) const {
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 4; ++k) p += at.weights[k] * x.segment<3>(3 * at.nodes[k]);
  return p;
}

Vec3 Grid::smooth_position(const VecX& x, const Vec2& uv_m) const {
  const double u = std::clamp(uv_m.x(), 0.0, width_m()), v = std::clamp(uv_m.y(), 0.0, height_m());
  // Four lines around the point along one axis and their Lagrange weights.
  const auto window = [](const std::vector<double>& lines, double t, int first[1], double w[4]) {
    const int n = static_cast<int>(lines.size());
    const int count = std::min(4, n);
    int start = std::clamp(cell_index(lines, t) - 1, 0, n - count);
    first[0] = start;
    for (int a = 0; a < 4; ++a) w[a] = 0.0;
    for (int a = 0; a < count; ++a) {
      double l = 1.0;
      for (int b = 0; b < count; ++b) {
        if (b != a) l *= (t - lines[start + b]) / (lines[start + a] - lines[start + b]);
      }
      w[a] = l;
    }
    return count;
  };
  int i0[1], j0[1];
  double wu[4], wv[4];
  const int cu = window(u_, u, i0, wu), cv = window(v_, v, j0, wv);
  Vec3 p = Vec3::Zero();
  for (int b = 0; b < cv; ++b) {
    for (int a = 0; a < cu; ++a) p += wu[a] * wv[b] * x.segment<3>(3 * node(i0[0] + a, j0[0] + b));
  }
  return p;
}

Vec2 Grid::cell_size_at(const Vec2& uv_m) const {
  const int i = cell_index(u_, std::clamp(uv_m.x(), 0.0, width_m()));
  const int j = cell_index(v_, std::clamp(uv_m.y(), 0.0, height_m()));
  return Vec2(du(i), dv(j));
}

}  // namespace sim_hw::real_sheet
