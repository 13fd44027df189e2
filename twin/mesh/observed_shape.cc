#include "twin/mesh/observed_shape.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace twin {

VecX shape_from_markers(const SheetMesh& mesh, const std::vector<Vec2>& marker_uv_m,
                        const std::vector<Vec3>& observed_m, const ObservedShapeOptions& options) {
  if (marker_uv_m.size() != observed_m.size()) {
    throw std::invalid_argument(fmt::format("shape_from_markers: {} marker positions for {} markers",
                                            observed_m.size(), marker_uv_m.size()));
  }
  std::vector<int> seen;
  for (std::size_t i = 0; i < observed_m.size(); ++i) {
    if (observed_m[i].allFinite()) seen.push_back(static_cast<int>(i));
  }
  if (seen.size() < 3) {
    throw std::invalid_argument(fmt::format("shape_from_markers: {} markers seen, at least 3 needed", seen.size()));
  }
  const int k = std::clamp(options.neighbours, 3, static_cast<int>(seen.size()));
  VecX x(3 * mesh.vertex_count());
  std::vector<std::pair<double, int>> by_distance(seen.size());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Vec2& uv = mesh.rest_uv[v];
    for (std::size_t j = 0; j < seen.size(); ++j) {
      by_distance[j] = {(marker_uv_m[seen[j]] - uv).squaredNorm(), seen[j]};
    }
    std::partial_sort(by_distance.begin(), by_distance.begin() + k, by_distance.end());
    // Weight width: the distance to the k-th marker, so the fit is local but never degenerate.
    const double h2 = std::max(by_distance[k - 1].first, 1e-12);
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // columns: x, y, z
    for (int j = 0; j < k; ++j) {
      const int m = by_distance[j].second;
      const Vec2 d = marker_uv_m[m] - uv;
      const Eigen::Vector3d basis(1.0, d.x(), d.y());
      const double w = std::exp(-by_distance[j].first / h2);
      normal += w * basis * basis.transpose();
      rhs += w * basis * observed_m[m].transpose();
    }
    // Markers nearly on a line leave the affine part undetermined; a tiny ridge keeps the
    // constant term (the vertex position) well defined.
    normal.diagonal() += 1e-9 * normal.trace() * Eigen::Vector3d::Ones();
    const Eigen::Matrix3d coefficients = normal.ldlt().solve(rhs);
    x.segment<3>(3 * v) = coefficients.row(0).transpose();
  }
  return x;
}

}  // namespace twin
