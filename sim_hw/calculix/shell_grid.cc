#include "sim_hw/calculix/shell_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::calculix {
namespace {

// Element edges along one side: 0, length, every cut, and equal spans of at most h between.
std::vector<double> lines(double length_m, double h_m, std::vector<double> cuts, const char* axis) {
  for (double c : cuts) {
    if (!(c >= 0 && c <= length_m)) {
      throw std::invalid_argument(fmt::format("CalculiX grid: cut {} m along {} is off the sheet [0, {}] m", c, axis, length_m));
    }
  }
  cuts.push_back(0);
  cuts.push_back(length_m);
  std::sort(cuts.begin(), cuts.end());
  std::vector<double> merged;
  for (double c : cuts) {
    if (merged.empty() || c - merged.back() > 1e-9) merged.push_back(c);
  }
  std::vector<double> out{merged.front()};
  for (std::size_t k = 1; k < merged.size(); ++k) {
    const double a = merged[k - 1], b = merged[k];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a) / h_m - 1e-9)));
    for (int s = 1; s <= n; ++s) out.push_back(s == n ? b : a + (b - a) * s / n);
  }
  return out;
}

}  // namespace

ShellGrid::ShellGrid(double width_m, double height_m, double element_size_m, std::vector<double> u_cuts_m,
                     std::vector<double> v_cuts_m) {
  if (!(width_m > 0) || !(height_m > 0) || !(element_size_m > 0)) {
    throw std::invalid_argument(fmt::format("CalculiX grid: sheet {} x {} m, element size {} m (expected positive)",
                                            width_m, height_m, element_size_m));
  }
  u_lines_ = lines(width_m, element_size_m, std::move(u_cuts_m), "u");
  v_lines_ = lines(height_m, element_size_m, std::move(v_cuts_m), "v");
  const int ni = 2 * eu() + 1, nj = 2 * ev() + 1;
  lattice_id_.assign(static_cast<std::size_t>(ni) * nj, -1);
  for (int j = 0; j < nj; ++j) {
    for (int i = 0; i < ni; ++i) {
      if (i % 2 == 1 && j % 2 == 1) continue;  // an element's centre
      const double u = i % 2 == 0 ? u_lines_[i / 2] : 0.5 * (u_lines_[i / 2] + u_lines_[i / 2 + 1]);
      const double v = j % 2 == 0 ? v_lines_[j / 2] : 0.5 * (v_lines_[j / 2] + v_lines_[j / 2 + 1]);
      node_uv_.emplace_back(u, v);
      lattice_id_[j * ni + i] = ++node_count_;
    }
  }
}

std::array<int, 8> ShellGrid::element_nodes(int e) const {
  const int i = 2 * (e % eu()), j = 2 * (e / eu());
  return {node_id(i, j),         node_id(i + 2, j),     node_id(i + 2, j + 2), node_id(i, j + 2),
          node_id(i + 1, j),     node_id(i + 2, j + 1), node_id(i + 1, j + 2), node_id(i, j + 1)};
}

ShellGrid::Location ShellGrid::locate(const Vec2& uv_m) const {
  const auto span = [](const std::vector<double>& l, double x, double* local) {
    x = std::clamp(x, l.front(), l.back());
    const auto it = std::upper_bound(l.begin() + 1, l.end() - 1, x);
    const int k = static_cast<int>(it - l.begin()) - 1;
    *local = 2.0 * (x - l[k]) / (l[k + 1] - l[k]) - 1.0;
    return k;
  };
  Location loc;
  const int a = span(u_lines_, uv_m.x(), &loc.xi), b = span(v_lines_, uv_m.y(), &loc.eta);
  loc.element = b * eu() + a;
  return loc;
}

std::array<double, 8> s8_shape(double x, double y) {
  return {0.25 * (1 - x) * (1 - y) * (-x - y - 1), 0.25 * (1 + x) * (1 - y) * (x - y - 1),
          0.25 * (1 + x) * (1 + y) * (x + y - 1),  0.25 * (1 - x) * (1 + y) * (-x + y - 1),
          0.5 * (1 - x * x) * (1 - y),             0.5 * (1 + x) * (1 - y * y),
          0.5 * (1 - x * x) * (1 + y),             0.5 * (1 - x) * (1 - y * y)};
}

}  // namespace sim_hw::calculix
