#include "twin/diagnosis/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

namespace twin::diagnosis {
namespace {

// Median of the chi-square distribution with one degree of freedom.
constexpr double kChiSquare1Median = 0.454936423119572;
constexpr int kNeighbours = 8;
constexpr std::size_t kMinDifferences = 16;
// Third differences cancel a locally quadratic field, not only a linear one: on a lab trial
// with twice the bending rigidity (residual RMS 3.5 mm, sigma 0.3 mm) the estimate was 25 %
// high from second differences, 18 % from third, 15 % from fourth (whose reach, five markers,
// leaves fewer differences on small grids).
constexpr int kGridDifferenceOrder = 3;

// Differences of order `order` along the rows and columns of a marker grid, d = sum_k c_k r(k)
// with binomial weights of alternating sign: d^2 / sum c_k^2 per coordinate.
void grid_differences(const ResidualField& field, const std::vector<int>& samples, Vec3 ResidualSample::*value, int rows,
                      int cols, int order, std::vector<double>& scaled) {
  std::vector<const Vec3*> at(static_cast<std::size_t>(rows) * cols, nullptr);
  for (int i : samples) {
    const int m = field.samples[i].marker;
    if (m >= 0 && m < rows * cols) at[m] = &(field.samples[i].*value);
  }
  std::vector<double> c(order + 1, 1.0);
  for (int k = 1; k <= order; ++k) c[k] = -c[k - 1] * (order - k + 1) / k;
  double norm = 0.0;
  for (double w : c) norm += w * w;
  auto add = [&](int first, int step) {
    Vec3 d = Vec3::Zero();
    for (int k = 0; k <= order; ++k) {
      const Vec3* r = at[first + k * step];
      if (!r) return;
      d += c[k] * *r;
    }
    for (int k = 0; k < 3; ++k) scaled.push_back(d(k) * d(k) / norm);
  };
  for (int r = 0; r < rows; ++r)
    for (int col = 0; col + order < cols; ++col) add(r * cols + col, 1);
  for (int r = 0; r + order < rows; ++r)
    for (int col = 0; col < cols; ++col) add(r * cols + col, cols);
}

// Each marker against the plane (in u, v) fitted to its nearest neighbours' residuals:
// d^2 / (1 + h) per coordinate, h = x0^T (X^T X)^-1 x0 the plane's variance factor at the marker.
void neighbour_differences(const ResidualField& field, const std::vector<int>& samples, Vec3 ResidualSample::*value,
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
      Y.row(row) = (s.*value).transpose();
      ++row;
    }
    const Eigen::Matrix3d XtX = X.transpose() * X;
    Eigen::LDLT<Eigen::Matrix3d> ldlt(XtX);
    if (ldlt.info() != Eigen::Success || std::abs(XtX.determinant()) < 1e-30) continue;
    const Eigen::Matrix3d coef = ldlt.solve(X.transpose() * Y);
    const double h = ldlt.solve(Eigen::Vector3d::UnitX())(0);
    if (!std::isfinite(h) || h <= 0.0) continue;
    const Vec3 d = field.samples[samples[a]].*value - coef.row(0).transpose();
    for (int k = 0; k < 3; ++k) scaled.push_back(d(k) * d(k) / (1.0 + h));
  }
}

// The robust scale of the differences of one quantity of every sample (residual or observation).
struct Scale {
  double sigma_m = std::numeric_limits<double>::infinity();
  int count = 0;
  bool grid = false, neighbours = false;
};

Scale difference_scale(const ResidualField& field, Vec3 ResidualSample::*value) {
  std::vector<double> scaled;
  Scale out;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    const std::vector<int> samples = field.samples_of_stage(s);
    const FieldTrial& trial = field.trials.at(field.stages[s].trial);
    const std::size_t before = scaled.size();
    if (trial.grid_rows && trial.grid_cols && *trial.grid_rows * *trial.grid_cols == trial.marker_count) {
      grid_differences(field, samples, value, *trial.grid_rows, *trial.grid_cols, kGridDifferenceOrder, scaled);
      out.grid = out.grid || scaled.size() > before;
    } else {
      neighbour_differences(field, samples, value, scaled);
      out.neighbours = out.neighbours || scaled.size() > before;
    }
  }
  out.count = static_cast<int>(scaled.size());
  if (scaled.size() < kMinDifferences) return out;
  const auto mid = scaled.begin() + static_cast<std::ptrdiff_t>(scaled.size() / 2);
  std::nth_element(scaled.begin(), mid, scaled.end());
  out.sigma_m = std::sqrt(*mid / kChiSquare1Median);
  return out;
}

}  // namespace

NoiseEstimate estimate_noise(const ResidualField& field) {
  const Scale residual = difference_scale(field, &ResidualSample::residual_m);
  if (residual.count < static_cast<int>(kMinDifferences))
    throw std::invalid_argument("noise estimate: only " + std::to_string(residual.count) +
                                " scalar marker differences in the residual field; expected at least " +
                                std::to_string(kMinDifferences) + " (give the noise level instead)");
  const Scale observed = difference_scale(field, &ResidualSample::observed_m);
  NoiseEstimate out;
  out.from_residuals_m = residual.sigma_m;
  out.from_observations_m = observed.sigma_m;
  const bool use_observed = observed.sigma_m < residual.sigma_m;
  const Scale& used = use_observed ? observed : residual;
  out.sigma_m = used.sigma_m;
  out.differences_used = used.count;
  // Appended, not `std::string(...) + "..."`: GCC 12 warns falsely (-Warray-bounds) on that sum.
  out.method = used.grid && used.neighbours ? "grid third differences and neighbour planes"
               : used.grid                  ? "grid third differences"
                                            : "neighbour planes";
  out.method += use_observed ? " of the observed markers" : " of the residuals";
  return out;
}

}  // namespace twin::diagnosis
