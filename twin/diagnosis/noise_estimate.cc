#include "twin/diagnosis/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

namespace twin::diagnosis {
namespace {

// Median of the chi-square distribution with one degree of freedom.
constexpr double kChiSquare1Median = 0.454936423119572;
constexpr int kNeighbours = 8;

// Second differences along the rows and columns of a marker grid: d^2 / 6 per coordinate.
void grid_differences(const ResidualField& field, const std::vector<int>& samples, int rows, int cols,
                      std::vector<double>& scaled) {
  std::vector<const Vec3*> at(static_cast<std::size_t>(rows) * cols, nullptr);
  for (int i : samples) {
    const int m = field.samples[i].marker;
    if (m >= 0 && m < rows * cols) at[m] = &field.samples[i].residual_m;
  }
  auto add = [&](int a, int b, int c) {
    if (!at[a] || !at[b] || !at[c]) return;
    const Vec3 d = *at[a] - 2.0 * *at[b] + *at[c];
    for (int k = 0; k < 3; ++k) scaled.push_back(d(k) * d(k) / 6.0);
  };
  for (int r = 0; r < rows; ++r)
    for (int c = 1; c + 1 < cols; ++c) add(r * cols + c - 1, r * cols + c, r * cols + c + 1);
  for (int r = 1; r + 1 < rows; ++r)
    for (int c = 0; c < cols; ++c) add((r - 1) * cols + c, r * cols + c, (r + 1) * cols + c);
}

// Each marker against the plane (in u, v) fitted to its nearest neighbours' residuals:
// d^2 / (1 + h) per coordinate, h = x0^T (X^T X)^-1 x0 the plane's variance factor at the marker.
void neighbour_differences(const ResidualField& field, const std::vector<int>& samples,
                           std::vector<double>& scaled) {
  const int n = static_cast<int>(samples.size());
  if (n < kNeighbours + 1) return;
  std::vector<std::pair<double, int>> by_distance(n);
  for (int a = 0; a < n; ++a) {
    const Vec2& uv = field.samples[samples[a]].uv_m;
    for (int b = 0; b < n; ++b) by_distance[b] = {(field.samples[samples[b]].uv_m - uv).squaredNorm(), b};
    std::partial_sort(by_distance.begin(), by_distance.begin() + kNeighbours + 1, by_distance.end());
    Eigen::Matrix<double, kNeighbours, 3> X;
    Eigen::Matrix<double, kNeighbours, 3> Y;
    int row = 0;
    for (int k = 0; k <= kNeighbours && row < kNeighbours; ++k) {
      const int b = by_distance[k].second;
      if (b == a) continue;
      const ResidualSample& s = field.samples[samples[b]];
      // Centred on the marker, so the plane's value there is its intercept.
      X.row(row) << 1.0, s.uv_m.x() - uv.x(), s.uv_m.y() - uv.y();
      Y.row(row) = s.residual_m.transpose();
      ++row;
    }
    const Eigen::Matrix3d XtX = X.transpose() * X;
    Eigen::LDLT<Eigen::Matrix3d> ldlt(XtX);
    if (ldlt.info() != Eigen::Success || std::abs(XtX.determinant()) < 1e-30) continue;
    const Eigen::Matrix3d coef = ldlt.solve(X.transpose() * Y);
    const double h = ldlt.solve(Eigen::Vector3d::UnitX())(0);
    if (!std::isfinite(h) || h <= 0.0) continue;
    const Vec3 d = field.samples[samples[a]].residual_m - coef.row(0).transpose();
    for (int k = 0; k < 3; ++k) scaled.push_back(d(k) * d(k) / (1.0 + h));
  }
}

}  // namespace

NoiseEstimate estimate_noise(const ResidualField& field) {
  std::vector<double> scaled;
  bool used_grid = false, used_neighbours = false;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    const std::vector<int> samples = field.samples_of_stage(s);
    const FieldTrial& trial = field.trials.at(field.stages[s].trial);
    const std::size_t before = scaled.size();
    if (trial.grid_rows && trial.grid_cols && *trial.grid_rows * *trial.grid_cols == trial.marker_count) {
      grid_differences(field, samples, *trial.grid_rows, *trial.grid_cols, scaled);
      used_grid = used_grid || scaled.size() > before;
    } else {
      neighbour_differences(field, samples, scaled);
      used_neighbours = used_neighbours || scaled.size() > before;
    }
  }
  if (scaled.size() < 16)
    throw std::invalid_argument("noise estimate: only " + std::to_string(scaled.size()) +
                                " scalar marker differences in the residual field; expected at least 16 "
                                "(give the noise level instead)");
  const auto mid = scaled.begin() + static_cast<std::ptrdiff_t>(scaled.size() / 2);
  std::nth_element(scaled.begin(), mid, scaled.end());
  NoiseEstimate out;
  out.sigma_m = std::sqrt(*mid / kChiSquare1Median);
  out.differences_used = static_cast<int>(scaled.size());
  out.method = used_grid && used_neighbours ? "grid second differences and neighbour planes"
               : used_grid                  ? "grid second differences"
                                            : "neighbour planes";
  return out;
}

}  // namespace twin::diagnosis
