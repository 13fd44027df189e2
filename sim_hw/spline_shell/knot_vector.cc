#include "sim_hw/spline_shell/knot_vector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>
#include <unsupported/Eigen/Splines>

namespace sim_hw::spline_shell {
namespace {

using Basis = Eigen::Spline<double, 1, Eigen::Dynamic>;

}  // namespace

KnotVector::KnotVector(int degree, std::vector<double> breaks_m, std::vector<int> multiplicities)
    : degree_(degree), breaks_(std::move(breaks_m)), multiplicity_(std::move(multiplicities)) {
  if (degree_ < 2 || degree_ > 4) {
    throw std::invalid_argument(fmt::format("spline shell: degree {} (expected 2 to 4: the shell needs C1 bases)", degree_));
  }
  if (breaks_.size() < 2 || breaks_.front() != 0.0) {
    throw std::invalid_argument("spline shell: breakpoints must start at 0 and hold at least two values");
  }
  for (std::size_t k = 1; k < breaks_.size(); ++k) {
    if (!std::isfinite(breaks_[k]) || !(breaks_[k] > breaks_[k - 1])) {
      throw std::invalid_argument(fmt::format("spline shell: breakpoint {} is {} after {} (expected finite and increasing)",
                                              k, breaks_[k], breaks_[k - 1]));
    }
  }
  if (multiplicity_.empty()) multiplicity_.assign(breaks_.size(), 1);
  if (multiplicity_.size() != breaks_.size()) {
    throw std::invalid_argument(fmt::format("spline shell: {} multiplicities for {} breakpoints (expected one each)",
                                            multiplicity_.size(), breaks_.size()));
  }
  multiplicity_.front() = multiplicity_.back() = degree_ + 1;
  for (std::size_t k = 1; k + 1 < breaks_.size(); ++k) {
    if (multiplicity_[k] < 1 || multiplicity_[k] > degree_ - 1) {
      throw std::invalid_argument(fmt::format("spline shell: breakpoint {} m has multiplicity {} (expected 1 to {}: the "
                                              "shell needs C1)", breaks_[k], multiplicity_[k], degree_ - 1));
    }
  }
  std::vector<double> knots;
  for (std::size_t k = 0; k < breaks_.size(); ++k) knots.insert(knots.end(), multiplicity_[k], breaks_[k]);
  knots_ = Eigen::Map<const Eigen::Array<double, 1, Eigen::Dynamic>>(knots.data(), static_cast<int>(knots.size()));
  // Element e spans knots t_s < t_(s+1), s the last copy of breakpoint e; its first basis is s - p.
  int s = -1;
  for (int e = 0; e < element_count(); ++e) {
    s += multiplicity_[e];
    first_.push_back(s - degree_);
  }
}

std::pair<int, int> KnotVector::basis_meeting(double lo_m, double hi_m) const {
  // Basis i lives on [t_i, t_(i+p+1)].
  int first = -1, last = -1;
  for (int i = 0; i < basis_count(); ++i) {
    if (knots_(i) < hi_m && knots_(i + degree_ + 1) > lo_m) {
      if (first < 0) first = i;
      last = i;
    }
  }
  return {first, last};
}

int KnotVector::element_at(double u_m) const {
  const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), u_m);
  const int e = static_cast<int>(it - breaks_.begin()) - 1;
  return std::clamp(e, 0, element_count() - 1);
}

KnotVector::Values KnotVector::evaluate(double u_m, int derivatives) const {
  return evaluate_in(element_at(u_m), u_m, derivatives);
}

KnotVector::Values KnotVector::evaluate_in(int element, double u_m, int derivatives) const {
  // Eigen finds the span itself; a point on a breakpoint belongs to the span above it, so a point
  // of element e is nudged inside e by clamping (the basis is continuous there up to order p-1,
  // and a derivative of order p is asked only at interior quadrature points).
  const double lo = breaks_[element], hi = breaks_[element + 1];
  const double u = std::clamp(u_m, lo, std::nextafter(hi, lo));
  Values out;
  out.first = first_[element];
  out.values = Basis::BasisFunctionDerivatives(u, derivatives, degree_, knots_);
  return out;
}

std::vector<double> KnotVector::greville() const {
  std::vector<double> g(basis_count());
  for (int i = 0; i < basis_count(); ++i) {
    double sum = 0;
    for (int k = 1; k <= degree_; ++k) sum += knots_(i + k);
    g[i] = sum / degree_;
  }
  return g;
}

Eigen::MatrixXd prolongation(const KnotVector& coarse, const KnotVector& fine) {
  if (coarse.degree() != fine.degree()) {
    throw std::invalid_argument(fmt::format("spline shell: prolongation from degree {} to {} (expected equal degrees)",
                                            coarse.degree(), fine.degree()));
  }
  for (std::size_t k = 0; k < coarse.breaks().size(); ++k) {
    const double b = coarse.breaks()[k];
    const auto& f = fine.breaks();
    const auto it = std::find_if(f.begin(), f.end(), [&](double x) { return std::abs(x - b) <= 1e-12 * coarse.length_m(); });
    if (it == f.end()) {
      throw std::invalid_argument(fmt::format("spline shell: the finer space has no breakpoint at {} m of the coarser", b));
    }
    if (fine.multiplicities()[it - f.begin()] < coarse.multiplicities()[k]) {
      throw std::invalid_argument(fmt::format("spline shell: the finer space's knot at {} m is of lower multiplicity", b));
    }
  }
  const std::vector<double> g = fine.greville();
  const int nf = fine.basis_count(), nc = coarse.basis_count();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nf, nf), B = Eigen::MatrixXd::Zero(nf, nc);
  for (int i = 0; i < nf; ++i) {
    const KnotVector::Values a = fine.evaluate(g[i], 0), b = coarse.evaluate(g[i], 0);
    for (int k = 0; k <= fine.degree(); ++k) A(i, a.first + k) = a.values(0, k);
    for (int k = 0; k <= coarse.degree(); ++k) B(i, b.first + k) = b.values(0, k);
  }
  Eigen::MatrixXd T = A.partialPivLu().solve(B);
  T = (T.array().abs() < 1e-14).select(0.0, T);  // knot insertion's zeros, exactly
  return T;
}

GaussRule gauss_legendre(int n, double a, double b) {
  // Golub-Welsch: the nodes are the eigenvalues of the Jacobi matrix of the Legendre recurrence,
  // the weights 2 v_0^2 from its normalised eigenvectors.
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
  for (int k = 1; k < n; ++k) J(k, k - 1) = J(k - 1, k) = k / std::sqrt(4.0 * k * k - 1.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(J);
  GaussRule rule;
  for (int k = 0; k < n; ++k) {
    const double t = eig.eigenvalues()(k), w = 2.0 * eig.eigenvectors()(0, k) * eig.eigenvectors()(0, k);
    rule.points.push_back(0.5 * (a + b) + 0.5 * (b - a) * t);
    rule.weights.push_back(0.5 * (b - a) * w);
  }
  return rule;
}

}  // namespace sim_hw::spline_shell
