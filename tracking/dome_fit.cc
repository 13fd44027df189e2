#include "tracking/dome_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tracking {
namespace {

constexpr int kMaxIterations = 50;
constexpr double kStepToleranceM = 1e-9;  // far below any scanner's resolution
constexpr int kTrimRounds = 3;

double rms_distance(const std::vector<Vec3>& points, double radius, const Vec3& centre) {
  double sum = 0.0;
  for (const Vec3& p : points) {
    const double f = (p - centre).norm() - radius;
    sum += f * f;
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

// Gauss-Newton on sum_i (|p_i - c| - r)^2 over c. The residual's gradient in c is the unit
// vector from the point to c, so the normal matrix is sum u u^T (well conditioned for any dome
// patch wider than a few degrees) and each step costs one pass over the points.
struct RoundResult {
  Vec3 centre;
  int iterations = 0;
  bool converged = false;
};

RoundResult gauss_newton(const std::vector<Vec3>& points, double radius, Vec3 centre) {
  RoundResult result;
  for (int it = 0; it < kMaxIterations; ++it) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Vec3 rhs = Vec3::Zero();
    for (const Vec3& p : points) {
      const Vec3 d = p - centre;
      const double distance = d.norm();
      if (distance < 1e-12) continue;  // direction undefined; one point does not matter
      const Vec3 u = d / distance;
      normal += u * u.transpose();
      rhs += u * (distance - radius);
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(normal);
    if (ldlt.info() != Eigen::Success) break;
    Vec3 step = ldlt.solve(rhs);
    if (!step.allFinite()) break;
    // A step longer than the radius means the linearisation is meaningless there; shorten it
    // so a poor start walks toward the points instead of jumping past them.
    const double length = step.norm();
    if (length > radius) step *= radius / length;
    centre += step;
    result.iterations = it + 1;
    if (length < kStepToleranceM) {
      result.converged = true;
      break;
    }
  }
  result.centre = centre;
  return result;
}

}  // namespace

Vec3 dome_bulge_direction(const std::vector<Vec3>& points) {
  if (points.size() < 3) return Vec3::UnitZ();
  const Vec3 mean = centroid_of(points);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  Vec3 axis = eigen.eigenvectors().col(0);  // eigenvalues ascend: column 0 is the flattest axis
  // Height along the axis against squared distance from it: a dome bulging toward +axis has its
  // rim low, so the two are negatively correlated.
  double correlation = 0.0;
  for (const Vec3& p : points) {
    const Vec3 d = p - mean;
    const double height = axis.dot(d);
    correlation += height * (d.squaredNorm() - height * height);
  }
  return correlation > 0.0 ? Vec3(-axis) : axis;
}

DomeFit fit_dome_sphere(const std::vector<Vec3>& points, double radius,
                        const std::vector<Vec3>& start_centres) {
  DomeFit fit;
  if (points.size() < 4 || start_centres.empty()) return fit;

  // Round 0 from every start; a start on the convex side can settle on the mirror sphere, whose
  // RMS is far worse, so the lowest RMS picks the right side.
  RoundResult best;
  double best_rms = std::numeric_limits<double>::infinity();
  for (const Vec3& start : start_centres) {
    const RoundResult r = gauss_newton(points, radius, start);
    fit.iterations += r.iterations;
    const double rms = rms_distance(points, radius, r.centre);
    if (rms < best_rms) {
      best_rms = rms;
      best = r;
    }
  }

  std::vector<Vec3> kept = points;
  for (int round = 0; round < kTrimRounds; ++round) {
    std::vector<double> residuals;
    residuals.reserve(kept.size());
    for (const Vec3& p : kept) residuals.push_back(std::abs((p - best.centre).norm() - radius));
    std::vector<double> sorted = residuals;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    // 1.4826 * median |residual| estimates the noise sigma for Gaussian noise without being
    // pulled by the outliers it is meant to find; the floor keeps noise-free data from being
    // trimmed on rounding.
    const double robust_sigma = 1.4826 * sorted[sorted.size() / 2];
    const double limit = std::max(4.0 * robust_sigma, 0.02 * radius);
    std::vector<Vec3> inliers;
    inliers.reserve(kept.size());
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (residuals[i] <= limit) inliers.push_back(kept[i]);
    }
    if (inliers.size() == kept.size() || inliers.size() < 4) break;
    kept = std::move(inliers);
    best = gauss_newton(kept, radius, best.centre);
    fit.iterations += best.iterations;
  }

  fit.base_centre_m = best.centre;
  fit.converged = best.converged;
  fit.kept_points = static_cast<int>(kept.size());
  fit.rms_m = rms_distance(kept, radius, best.centre);
  return fit;
}

Vec3 centroid_of(const std::vector<Vec3>& points) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

Vec3 dome_centroid_offset(const std::vector<Vec3>& points, double radius, const Vec3& normal) {
  return centroid_of(points) - 0.5 * radius * normal.normalized();
}

}  // namespace tracking
