#include "twin/diagnosis/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
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

// Markers of one stage (or one difference of two scans): material coordinates and a value.
struct MarkerValues {
  std::vector<Vec2> uv_m;
  std::vector<Vec3> value;
};

// Appends d^2 / (variance_factor (1 + h)) per coordinate for each marker whose neighbours
// determine the polynomial: variance_factor is 1 for a single scan, 2 for the difference of two.
void neighbour_differences(const MarkerValues& markers, int degree, int neighbours, double variance_factor,
                           std::vector<double>& scaled) {
  const int n = static_cast<int>(markers.uv_m.size());
  if (n < neighbours + 1) return;
  std::vector<std::pair<double, int>> by_distance(n);
  std::vector<Vec2> offsets;
  Eigen::MatrixXd Y(neighbours, 3);
  for (int a = 0; a < n; ++a) {
    const Vec2& uv = markers.uv_m[a];
    for (int b = 0; b < n; ++b) by_distance[b] = {(markers.uv_m[b] - uv).squaredNorm(), b};
    std::partial_sort(by_distance.begin(), by_distance.begin() + neighbours + 1, by_distance.end());
    const double reach = std::sqrt(by_distance[neighbours].first);
    if (!(reach > 0.0)) continue;
    offsets.clear();
    for (int k = 0; k <= neighbours && static_cast<int>(offsets.size()) < neighbours; ++k) {
      const int b = by_distance[k].second;
      if (b == a) continue;
      offsets.push_back((markers.uv_m[b] - uv) / reach);
      Y.row(static_cast<Eigen::Index>(offsets.size()) - 1) = markers.value[b].transpose();
    }
    if (static_cast<int>(offsets.size()) < neighbours) continue;
    // A marker whose neighbours do not determine the polynomial (at an edge, the nearest may
    // span too few rows for a quartic in v) is left out, whatever the listing: a lower degree
    // there cancels less of the sheet's shape (on independent-lab trials the estimate from the
    // observed markers rose by 7-9 % with them in at the highest degree they determine).
    Vec3 d;
    double h = 0.0;
    if (!fit_difference(offsets, Y, markers.value[a], degree, d, h)) continue;
    for (int c = 0; c < 3; ++c) scaled.push_back(d(c) * d(c) / (variance_factor * (1.0 + h)));
  }
}

// The highest degree the marker count allows: a stage with too few seen markers for the quartic
// gets a quadratic on 12, else a plane on 8 (they cancel less of a smooth field: an upper bound
// from that stage).
void local_fit_differences(const MarkerValues& markers, double variance_factor, std::vector<double>& scaled) {
  const int n = static_cast<int>(markers.uv_m.size());
  if (n > kNeighbours) neighbour_differences(markers, kFitDegree, kNeighbours, variance_factor, scaled);
  else if (n > 12) neighbour_differences(markers, 2, 12, variance_factor, scaled);
  else neighbour_differences(markers, 1, 8, variance_factor, scaled);
}

// The robust scale of a set of scaled squared differences.
struct Scale {
  double sigma_m = std::numeric_limits<double>::infinity();
  int count = 0;
};

Scale robust_scale(std::vector<double>& scaled) {
  Scale out;
  out.count = static_cast<int>(scaled.size());
  if (scaled.size() < kMinDifferences) return out;
  const auto mid = scaled.begin() + static_cast<std::ptrdiff_t>(scaled.size() / 2);
  std::nth_element(scaled.begin(), mid, scaled.end());
  out.sigma_m = std::sqrt(*mid / kChiSquare1Median);
  return out;
}

// One quantity of every sample (residual or observation), stage by stage.
Scale difference_scale(const ResidualField& field, Vec3 ResidualSample::*value) {
  std::vector<double> scaled;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    MarkerValues markers;
    for (int i : field.samples_of_stage(s)) {
      markers.uv_m.push_back(field.samples[i].uv_m);
      markers.value.push_back(field.samples[i].*value);
    }
    local_fit_differences(markers, 1.0, scaled);
  }
  return robust_scale(scaled);
}

// Repeated scans of one pose: for each stage and the next scan of its pose, the difference of
// the two observations of every marker both saw holds twice the noise variance plus what the
// sheet did between the scans (relaxation: smooth over the sheet, which the local fit cancels).
// The sheet's shape, folds and all, cancels in the difference. Consecutive pairs share a scan
// (a-b and b-c), so only every other pair of a pose is independent of the one before: the
// sampling error counts those (Scale::count stays every difference).
struct RepeatScale {
  Scale scale;
  int independent = 0;
};

RepeatScale repeated_scan_scale(const ResidualField& field) {
  std::vector<double> scaled;
  RepeatScale out;
  int pair_in_group = 0;
  for (int s = 0; s + 1 < static_cast<int>(field.stages.size()); ++s) {
    if (field.stages[s].pose_group < 0 || field.stages[s + 1].pose_group != field.stages[s].pose_group) {
      pair_in_group = 0;
      continue;
    }
    std::map<int, const ResidualSample*> first;
    for (int i : field.samples_of_stage(s)) first[field.samples[i].marker] = &field.samples[i];
    MarkerValues difference;
    for (int i : field.samples_of_stage(s + 1)) {
      const auto it = first.find(field.samples[i].marker);
      if (it == first.end()) continue;
      difference.uv_m.push_back(it->second->uv_m);
      difference.value.push_back(field.samples[i].observed_m - it->second->observed_m);
    }
    const std::size_t before = scaled.size();
    local_fit_differences(difference, 2.0, scaled);
    if (pair_in_group++ % 2 == 0) out.independent += static_cast<int>(scaled.size() - before);
  }
  out.scale = robust_scale(scaled);
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
  const RepeatScale repeated = repeated_scan_scale(field);
  NoiseEstimate out;
  out.from_residuals_m = residual.sigma_m;
  out.from_observations_m = observed.sigma_m;
  out.from_repeated_scans_m = repeated.scale.sigma_m;
  // Var(sample median) = 1 / (4 N f(m)^2), f the chi-square(1) density at its median m; sigma
  // goes as the median's square root: 0.5 / (2 f(m) m) / sqrt(N) = 1.166 / sqrt(N).
  const auto standard_error = [](int n) { return 1.166 / std::sqrt(static_cast<double>(std::max(n, 1))); };
  if (std::isfinite(repeated.scale.sigma_m)) {
    out.sigma_m = repeated.scale.sigma_m;
    out.differences_used = repeated.scale.count;
    out.relative_standard_error = standard_error(repeated.independent);
    out.method = "repeated scans of one pose";
    return out;
  }
  const bool use_observed = observed.sigma_m < residual.sigma_m;
  const Scale& used = use_observed ? observed : residual;
  out.sigma_m = used.sigma_m;
  out.differences_used = used.count;
  out.relative_standard_error = standard_error(used.count);
  out.method = use_observed ? "local quartic fits of the observed markers" : "local quartic fits of the residuals";
  return out;
}

}  // namespace twin::diagnosis
