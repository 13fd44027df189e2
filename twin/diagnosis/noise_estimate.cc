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
constexpr std::size_t kMinDifferences = 16;
// Each marker is compared with a quartic fitted to its 24 nearest markers (on a grid, the 5 x 5
// block around it). On independent-lab trials (composite, 17 x 17 markers 6-7 cm apart, folds
// of 2-5 cm radius between them, 0.3 mm noise), from the observed markers: quadratic fits to 12
// neighbours 0.86 mm, cubic to 16 0.78 mm, quartic to 24 0.68 mm; the grid third differences
// used before gave 0.64 mm on the grid and the neighbour planes 2.12 mm on the same markers as a
// list. One method for every layout, so the estimate does not depend on how the markers are
// listed. Still 2.3x the true noise there: markers this far apart do not resolve the folds
// (noise_estimate.h, LIMIT).
constexpr int kFitDegree = 4;
constexpr int kNeighbours = 24;

// Each marker against the polynomial of degree kFitDegree in (u, v) fitted by least squares to
// its kNeighbours nearest markers (not itself): d = r - p(uv) per coordinate, whose variance
// for independent noise is sigma^2 (1 + h), h = x0^T (X^T X)^-1 x0 the fit's variance factor at
// the marker. Coordinates are centred on the marker and scaled by the farthest neighbour's
// distance, so x0 is the first unit vector and X^T X is well scaled.
int basis_size(int degree) { return (degree + 1) * (degree + 2) / 2; }

// The monomials x^i y^j, i + j <= degree, into row `row` of X.
void basis_row(double x, double y, int degree, Eigen::MatrixXd& X, int row) {
  int k = 0;
  for (int total = 0; total <= degree; ++total)
    for (int i = total; i >= 0; --i) X(row, k++) = std::pow(x, i) * std::pow(y, total - i);
}

// The fit's difference at the marker for one degree: d = value - p(0), and h; false when the
// neighbours do not determine a polynomial of that degree (e.g. at a sheet's edge, where the
// nearest markers span too few rows).
bool fit_difference(const std::vector<Vec2>& offsets, const Eigen::MatrixXd& Y, const Vec3& value, int degree,
                    Vec3& d, double& h) {
  const int rows = static_cast<int>(offsets.size());
  const int p = basis_size(degree);
  if (rows <= p) return false;
  Eigen::MatrixXd X(rows, p);
  for (int r = 0; r < rows; ++r) basis_row(offsets[r].x(), offsets[r].y(), degree, X, r);
  // QR, not the normal equations: a one-sided quartic squares badly.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  if (qr.rank() < p) return false;
  const Eigen::MatrixXd coef = qr.solve(Y);
  // h = e0^T (X^T X)^-1 e0 = |R^-T P^T e0|^2 with X P = Q R.
  const Eigen::VectorXd pe0 = qr.colsPermutation().transpose() * Eigen::VectorXd::Unit(p, 0);
  const Eigen::VectorXd w = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>().transpose().solve(pe0);
  h = w.squaredNorm();
  d = value - coef.row(0).transpose();
  return std::isfinite(h) && h > 0.0;
}

void neighbour_differences(const ResidualField& field, const std::vector<int>& samples, Vec3 ResidualSample::*value,
                           int degree, int neighbours, std::vector<double>& scaled) {
  const int n = static_cast<int>(samples.size());
  if (n < neighbours + 1) return;
  std::vector<std::pair<double, int>> by_distance(n);
  std::vector<Vec2> offsets;
  Eigen::MatrixXd Y(neighbours, 3);
  for (int a = 0; a < n; ++a) {
    const Vec2& uv = field.samples[samples[a]].uv_m;
    for (int b = 0; b < n; ++b) by_distance[b] = {(field.samples[samples[b]].uv_m - uv).squaredNorm(), b};
    std::partial_sort(by_distance.begin(), by_distance.begin() + neighbours + 1, by_distance.end());
    const double reach = std::sqrt(by_distance[neighbours].first);
    if (!(reach > 0.0)) continue;
    offsets.clear();
    for (int k = 0; k <= neighbours && static_cast<int>(offsets.size()) < neighbours; ++k) {
      const int b = by_distance[k].second;
      if (b == a) continue;
      const ResidualSample& s = field.samples[samples[b]];
      offsets.push_back((s.uv_m - uv) / reach);
      Y.row(static_cast<Eigen::Index>(offsets.size()) - 1) = (s.*value).transpose();
    }
    if (static_cast<int>(offsets.size()) < neighbours) continue;
    // A marker whose neighbours do not determine the polynomial (at an edge, the nearest may
    // span too few rows for a quartic in v) is left out, whatever the listing: a lower degree
    // there cancels less of the sheet's shape (on independent-lab trials the estimate from the
    // observed markers rose by 7-9 % with them in at the highest degree they determine).
    Vec3 d;
    double h = 0.0;
    if (!fit_difference(offsets, Y, field.samples[samples[a]].*value, degree, d, h)) continue;
    for (int c = 0; c < 3; ++c) scaled.push_back(d(c) * d(c) / (1.0 + h));
  }
}

// The robust scale of the differences of one quantity of every sample (residual or observation).
struct Scale {
  double sigma_m = std::numeric_limits<double>::infinity();
  int count = 0;
};

Scale difference_scale(const ResidualField& field, Vec3 ResidualSample::*value) {
  std::vector<double> scaled;
  Scale out;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    const std::vector<int> samples = field.samples_of_stage(s);
    // A stage with too few seen markers for the quartic gets a quadratic on 12, else a plane
    // on 8 (they cancel less of a smooth field: an upper bound from that stage).
    const int n = static_cast<int>(samples.size());
    if (n > kNeighbours) neighbour_differences(field, samples, value, kFitDegree, kNeighbours, scaled);
    else if (n > 12) neighbour_differences(field, samples, value, 2, 12, scaled);
    else neighbour_differences(field, samples, value, 1, 8, scaled);
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
  // Var(sample median) = 1 / (4 N f(m)^2), f the chi-square(1) density at its median m; sigma
  // goes as the median's square root: 0.5 / (2 f(m) m) / sqrt(N) = 1.166 / sqrt(N).
  out.relative_standard_error = 1.166 / std::sqrt(static_cast<double>(std::max(used.count, 1)));
  out.method = use_observed ? "local quartic fits of the observed markers" : "local quartic fits of the residuals";
  return out;
}

}  // namespace twin::diagnosis
