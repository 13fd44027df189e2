#include "twin/solvers/levenberg_marquardt.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

namespace twin {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// Rosenbrock's valley as least squares: r = (10 (y1 - y0^2), 1 - y0), minimum S = 0 at (1, 1).
LeastSquaresPoint rosenbrock(const VectorXd& y) {
  LeastSquaresPoint p;
  p.usable = true;
  p.residuals = VectorXd(2);
  p.residuals << 10.0 * (y(1) - y(0) * y(0)), 1.0 - y(0);
  p.jacobian = MatrixXd(2, 2);
  p.jacobian << -20.0 * y(0), 10.0, -1.0, 0.0;
  return p;
}

// Decay curve a exp(-b t) sampled at t = 0..9, data made with a = 2, b = 0.3.
LeastSquaresPoint decay(const VectorXd& y) {
  LeastSquaresPoint p;
  p.usable = true;
  p.residuals = VectorXd(10);
  p.jacobian = MatrixXd(10, 2);
  for (int k = 0; k < 10; ++k) {
    const double t = k;
    const double model = y(0) * std::exp(-y(1) * t);
    p.residuals(k) = model - 2.0 * std::exp(-0.3 * t);
    p.jacobian(k, 0) = std::exp(-y(1) * t);
    p.jacobian(k, 1) = -t * model;
  }
  return p;
}

const VectorXd kWide = VectorXd::Constant(2, 1e3);

}  // namespace

TEST_CASE("Levenberg-Marquardt walks Rosenbrock's valley to its minimum in few evaluations") {
  LevenbergMarquardtOptions o;
  o.max_evaluations = 100;
  o.x_tolerance = 1e-10;
  o.f_tolerance = 0.0;
  const LevenbergMarquardtResult r = levenberg_marquardt(rosenbrock, VectorXd::Map(std::array{-1.2, 1.0}.data(), 2),
                                                         -kWide, kWide, o);
  INFO(r.stop_reason << " after " << r.evaluations << " evaluations");
  CHECK(r.converged);
  CHECK(r.coordinates(0) == Approx(1.0).margin(1e-8));
  CHECK(r.coordinates(1) == Approx(1.0).margin(1e-8));
  CHECK(r.sum_squares < 1e-16);
  CHECK(r.evaluations < 40);
}

TEST_CASE("Levenberg-Marquardt fits a decay curve exactly") {
  LevenbergMarquardtOptions o;
  o.x_tolerance = 1e-12;
  o.f_tolerance = 0.0;
  const LevenbergMarquardtResult r =
      levenberg_marquardt(decay, VectorXd::Map(std::array{1.0, 1.0}.data(), 2), -kWide, kWide, o);
  INFO(r.stop_reason << " after " << r.evaluations << " evaluations");
  CHECK(r.evaluations < 30);
  CHECK(r.sum_squares < 1e-20);
  CHECK(r.coordinates(0) == Approx(2.0).epsilon(1e-6));
  CHECK(r.coordinates(1) == Approx(0.3).epsilon(1e-6));
}

TEST_CASE("Levenberg-Marquardt treats a failed evaluation as a rejected step and carries on") {
  // Evaluations with b < 0.5 "fail" (as a sheet that finds no equilibrium): the search starts at
  // b = 1 and must end on the usable side, at the best usable fit.
  int failures = 0;
  const auto guarded = [&](const VectorXd& y) {
    if (y(1) < 0.5) {
      ++failures;
      return LeastSquaresPoint{};
    }
    return decay(y);
  };
  LevenbergMarquardtOptions o;
  o.max_evaluations = 60;
  const LevenbergMarquardtResult r =
      levenberg_marquardt(guarded, VectorXd::Map(std::array{1.0, 2.0}.data(), 2), -kWide, kWide, o);
  INFO(r.stop_reason << "; " << failures << " failed evaluations");
  CHECK(r.coordinates(1) >= 0.5);
  CHECK(std::isfinite(r.sum_squares));
  // The best usable fit lies on the boundary b = 0.5 (the data's b is 0.3): the search got close.
  CHECK(r.coordinates(1) == Approx(0.5).margin(0.05));
}

TEST_CASE("Levenberg-Marquardt stays inside its bounds") {
  const VectorXd lower = VectorXd::Map(std::array{-5.0, 0.4}.data(), 2);
  const VectorXd upper = VectorXd::Map(std::array{1.5, 5.0}.data(), 2);
  const LevenbergMarquardtResult r =
      levenberg_marquardt(decay, VectorXd::Map(std::array{1.0, 1.0}.data(), 2), lower, upper, {});
  INFO(r.stop_reason);
  CHECK(r.coordinates(0) >= -5.0);
  CHECK(r.coordinates(0) <= 1.5);
  CHECK(r.coordinates(1) >= 0.4);
  CHECK(r.coordinates(1) <= 5.0);
  // The unbounded optimum (2, 0.3) is outside: the result sits on the box.
  CHECK((r.coordinates(0) == Approx(1.5) || r.coordinates(1) == Approx(0.4)));
}

TEST_CASE("Levenberg-Marquardt damps a step that leaves its bounds and goes uphill when cut back, and carries on") {
  // Linear least squares with a direction the data barely see: the Gauss-Newton step from 0 is
  // (3, -2); cut back to the box [-1, 1]^2 it is (1, -1), which raises S. The search must not
  // stop there (it did: "no descent direction left" at the start).
  const auto nearly_degenerate = [](const VectorXd& y) {
    LeastSquaresPoint p;
    p.usable = true;
    p.jacobian = MatrixXd(2, 2);
    p.jacobian << 1.0, 1.0, 1.0, 1.1;
    const Eigen::Vector2d data(1.0, 0.8);
    p.residuals = p.jacobian * y - data;
    return p;
  };
  const VectorXd start = VectorXd::Zero(2);
  const LevenbergMarquardtResult r =
      levenberg_marquardt(nearly_degenerate, start, VectorXd::Constant(2, -1.0), VectorXd::Constant(2, 1.0), {});
  INFO(r.stop_reason);
  CHECK(r.evaluations > 1);
  CHECK(r.sum_squares < 0.05);  // from 1.64 at the start; the box holds points with S < 0.01
  CHECK(r.coordinates.cwiseAbs().maxCoeff() <= 1.0);
}

TEST_CASE("Levenberg-Marquardt refuses a start without usable residuals") {
  const auto failing = [](const VectorXd&) { return LeastSquaresPoint{}; };
  CHECK_THROWS_AS(levenberg_marquardt(failing, VectorXd::Zero(2), -kWide, kWide, {}), std::invalid_argument);
  CHECK_THROWS_AS(levenberg_marquardt(decay, VectorXd::Zero(2), -VectorXd::Ones(3), VectorXd::Ones(3), {}),
                  std::invalid_argument);
}

}  // namespace twin
