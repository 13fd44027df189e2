#include <catch2/catch.hpp>

#include <cmath>

#include "twin/diagnosis/chi_square.h"

using twin::diagnosis::chi_square_upper_tail;
using twin::diagnosis::correlation_p_value;
using twin::diagnosis::upper_incomplete_gamma_q;

TEST_CASE("the chi-square tail matches tabulated quantiles", "[diagnosis]") {
  // 95 % and 99.9 % quantiles from standard tables.
  CHECK(chi_square_upper_tail(3.841459, 1) == Approx(0.05).epsilon(1e-5));
  CHECK(chi_square_upper_tail(18.307038, 10) == Approx(0.05).epsilon(1e-5));
  CHECK(chi_square_upper_tail(124.342113, 100) == Approx(0.05).epsilon(1e-5));
  CHECK(chi_square_upper_tail(29.588298, 10) == Approx(0.001).epsilon(1e-4));
  CHECK(chi_square_upper_tail(0.0, 5) == 1.0);
  // Far in the tail the continued fraction keeps relative accuracy.
  CHECK(chi_square_upper_tail(2000.0, 867) > 0.0);
  CHECK(chi_square_upper_tail(2000.0, 867) < 1e-60);
}

TEST_CASE("the incomplete gamma agrees with closed forms on both sides of a + 1", "[diagnosis]") {
  for (double x : {0.1, 0.7, 1.9, 2.5, 8.0, 40.0}) {
    // a = 1: Q = exp(-x); a = 2: Q = (1 + x) exp(-x).
    CHECK(upper_incomplete_gamma_q(1.0, x) == Approx(std::exp(-x)).epsilon(1e-10));
    CHECK(upper_incomplete_gamma_q(2.0, x) == Approx((1.0 + x) * std::exp(-x)).epsilon(1e-10));
    // a = 1/2: Q = erfc(sqrt(x)).
    CHECK(upper_incomplete_gamma_q(0.5, x) == Approx(std::erfc(std::sqrt(x))).epsilon(1e-9));
  }
  CHECK_THROWS(upper_incomplete_gamma_q(0.0, 1.0));
  CHECK_THROWS(chi_square_upper_tail(1.0, -2.0));
}

TEST_CASE("the correlation p-value is two-sided and needs enough pairs", "[diagnosis]") {
  CHECK(correlation_p_value(0.0, 100) == Approx(1.0));
  CHECK(correlation_p_value(0.3, 100) == Approx(correlation_p_value(-0.3, 100)));
  CHECK(correlation_p_value(0.3, 100) < 0.01);
  CHECK(correlation_p_value(0.9, 3) == 1.0);
}
