#include "twin/diagnosis/residual_structure.h"

#include <cmath>
#include <functional>

#include <Eigen/Dense>

namespace twin::diagnosis {
namespace {

constexpr double kNotableCorrelation = 0.2;
// A direction "dominates" when it explains at least this many times the other's fraction.
constexpr double kDominance = 1.5;
constexpr int kCubicTerms = 3;  // u, u^2, u^3 beyond the stage mean

// Sum of squares of y explained by a cubic in t beyond its mean (t scaled to [-1, 1] first
// for conditioning).
double explained_by_cubic(const std::vector<double>& t, const std::vector<double>& y) {
  const int n = static_cast<int>(y.size());
  double lo = t[0], hi = t[0];
  for (double v : t) lo = std::min(lo, v), hi = std::max(hi, v);
  if (hi - lo <= 1e-12) return 0.0;
  Eigen::MatrixXd X(n, kCubicTerms + 1);
  Eigen::VectorXd Y(n);
  for (int i = 0; i < n; ++i) {
    const double s = 2.0 * (t[i] - lo) / (hi - lo) - 1.0;
    X.row(i) << 1.0, s, s * s, s * s * s;
    Y(i) = y[i];
  }
  const Eigen::VectorXd fitted = X * X.colPivHouseholderQr().solve(Y);
  const double mean = Y.mean();
  return (fitted.array() - mean).square().sum();
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const int n = static_cast<int>(a.size());
  if (n < 3) return NAN;
  const Eigen::Map<const Eigen::ArrayXd> x(a.data(), n), y(b.data(), n);
  const Eigen::ArrayXd dx = x - x.mean(), dy = y - y.mean();
  const double sxx = dx.square().sum(), syy = dy.square().sum();
  if (sxx <= 0.0 || syy <= 0.0) return NAN;
  return (dx * dy).sum() / std::sqrt(sxx * syy);
}

Correlation correlate(const std::string& quantity, const std::vector<double>& q, const std::vector<double>& e,
                      double alpha) {
  std::vector<double> a, b;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (std::isfinite(q[i]) && std::isfinite(e[i])) a.push_back(q[i]), b.push_back(e[i]);
  Correlation c;
  c.quantity = quantity;
  const double r = pearson(a, b);
  if (!std::isfinite(r)) return c;
  c.r = r;
  c.samples = static_cast<int>(a.size());
  c.p_value = correlation_p_value(r, c.samples);
  c.notable = c.p_value < alpha && std::abs(r) >= kNotableCorrelation;
  return c;
}

}  // namespace

DirectionStructure analyse_direction(const ResidualField& field, double sigma_m, double alpha) {
  double total = 0.0, by_u = 0.0, by_v = 0.0;
  int dof = 0;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    const std::vector<int> idx = field.samples_of_stage(s);
    if (static_cast<int>(idx.size()) < 2 * (kCubicTerms + 1)) continue;
    std::vector<double> u, v, y;
    for (int i : idx) {
      u.push_back(field.samples[i].uv_m.x());
      v.push_back(field.samples[i].uv_m.y());
      y.push_back(field.samples[i].normal_residual_m);
    }
    double mean = 0.0;
    for (double r : y) mean += r;
    mean /= static_cast<double>(y.size());
    for (double r : y) total += (r - mean) * (r - mean);
    by_u += explained_by_cubic(u, y);
    by_v += explained_by_cubic(v, y);
    dof += kCubicTerms;
  }
  DirectionStructure out;
  if (dof == 0 || total <= 0.0) return out;
  out.explained_by_u = by_u / total;
  out.explained_by_v = by_v / total;
  // With sigma known, the explained sum of squares of pure noise is sigma^2 chi-square(dof).
  out.p_u = chi_square_upper_tail(by_u / (sigma_m * sigma_m), dof);
  out.p_v = chi_square_upper_tail(by_v / (sigma_m * sigma_m), dof);
  if (out.p_u < alpha && out.explained_by_u >= kDominance * out.explained_by_v) out.direction = "u";
  else if (out.p_v < alpha && out.explained_by_v >= kDominance * out.explained_by_u) out.direction = "v";
  return out;
}

std::vector<Correlation> analyse_correlations(const ResidualField& field, double alpha) {
  std::vector<double> error, distance, curvature;
  for (const ResidualSample& s : field.samples) {
    error.push_back(s.error_m());
    distance.push_back(s.clamp_distance_m);
    curvature.push_back(s.curvature_1_m);
  }
  std::vector<double> stage_rms, load, age;
  for (int s = 0; s < static_cast<int>(field.stages.size()); ++s) {
    double sum = 0.0;
    const std::vector<int> idx = field.samples_of_stage(s);
    for (int i : idx) sum += field.samples[i].residual_m.squaredNorm();
    stage_rms.push_back(idx.empty() ? NAN : std::sqrt(sum / (3.0 * idx.size())));
    load.push_back(field.stages[s].load_m);
    age.push_back(field.stages[s].age_s);
  }
  return {correlate("clamp distance", distance, error, alpha), correlate("curvature", curvature, error, alpha),
          correlate("stage load", load, stage_rms, alpha), correlate("stage age", age, stage_rms, alpha)};
}

}  // namespace twin::diagnosis
