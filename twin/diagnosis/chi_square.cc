#include "twin/diagnosis/chi_square.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace twin::diagnosis {
namespace {

constexpr int kMaxIterations = 100000;
constexpr double kEpsilon = 1e-15;
constexpr double kTiny = 1e-300;

// P(a, x) by the series e^-x x^a / Gamma(a + 1) sum_n x^n / ((a + 1) ... (a + n)).
double lower_series(double a, double x) {
  double term = 1.0 / a, sum = term, ap = a;
  for (int n = 0; n < kMaxIterations; ++n) {
    ap += 1.0;
    term *= x / ap;
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEpsilon) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by the continued fraction e^-x x^a / Gamma(a) (1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - ...))),
// evaluated with the modified Lentz method.
double upper_fraction(double a, double x) {
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double upper_incomplete_gamma_q(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0) || !std::isfinite(a))
    throw std::invalid_argument("upper incomplete gamma: need a > 0 and x >= 0");
  if (x == 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  if (x < a + 1.0) return std::clamp(1.0 - lower_series(a, x), 0.0, 1.0);
  return std::clamp(upper_fraction(a, x), 0.0, 1.0);
}

double chi_square_upper_tail(double x, double dof) {
  if (!(dof > 0.0)) throw std::invalid_argument("chi-square tail: dof must be positive");
  if (!(x > 0.0)) return 1.0;
  return upper_incomplete_gamma_q(0.5 * dof, 0.5 * x);
}

double correlation_p_value(double r, int n) {
  if (n < 4 || !std::isfinite(r)) return 1.0;
  const double rc = std::clamp(r, -1.0 + 1e-15, 1.0 - 1e-15);
  const double z = std::atanh(rc) * std::sqrt(n - 3.0);
  return std::erfc(std::abs(z) / std::sqrt(2.0));
}

}  // namespace twin::diagnosis
