#include "sim_hw/real_sheet/grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace sim_hw::real_sheet {

Grid::Grid(double width_m, double height_m, double max_spacing_m)
    : width_m_(width_m), height_m_(height_m) {
  if (!(width_m > 0) || !(height_m > 0) || !(max_spacing_m > 0) || !std::isfinite(width_m) ||
      !std::isfinite(height_m) || !std::isfinite(max_spacing_m)) {
    throw std::invalid_argument(fmt::format("real sheet grid: sheet {} x {} m with spacing {} m (all must be positive)",
                                            width_m, height_m, max_spacing_m));
  }
  nu_ = std::max(3, static_cast<int>(std::ceil(width_m / max_spacing_m - 1e-9)) + 1);
  nv_ = std::max(3, static_cast<int>(std::ceil(height_m / max_spacing_m - 1e-9)) + 1);
  du_ = width_m / (nu_ - 1);
  dv_ = height_m / (nv_ - 1);
}

double Grid::node_area_m2(int node) const {
  const int i = node % nu_, j = node / nu_;
  const double fu = (i == 0 || i == nu_ - 1) ? 0.5 : 1.0;
  const double fv = (j == 0 || j == nv_ - 1) ? 0.5 : 1.0;
  return fu * fv * du_ * dv_;
}

VecX Grid::flat_positions() const {
  VecX x = VecX::Zero(3 * node_count());
  for (int n = 0; n < node_count(); ++n) x.segment<2>(3 * n) = rest_uv(n);
  return x;
}

Grid::Location Grid::locate(const Vec2& uv_m) const {
  const double u = std::clamp(uv_m.x(), 0.0, width_m_) / du_, v = std::clamp(uv_m.y(), 0.0, height_m_) / dv_;
  const int i = std::min(static_cast<int>(u), nu_ - 2), j = std::min(static_cast<int>(v), nv_ - 2);
  const double a = u - i, b = v - j;
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

}  // namespace sim_hw::real_sheet
