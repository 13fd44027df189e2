// The reference sheet's spline space (sim_hw/spline_shell/knot_vector.h, spline_patch.h): the
// basis sums to one and its derivatives to zero, the flat sheet is exact, knot insertion
// represents a coarse surface exactly, the Gauss rule integrates what it promises, and bad
// input is refused with a message naming what was expected.

#include <cmath>
#include <random>

#include <catch2/catch.hpp>

#include "sim_hw/spline_shell/spline_patch.h"
#include "sim_hw/spline_shell/square_jaw.h"

namespace ss = sim_hw::spline_shell;

namespace {

ss::KnotVector graded(int degree, double length, int elements) {
  // Spans growing by 1.3: an unequal grading like the jaws' and folds'.
  std::vector<double> breaks = {0.0};
  double h = 1.0, sum = 0;
  for (int e = 0; e < elements; ++e) sum += h, h *= 1.3;
  h = length / sum;
  for (int e = 0; e < elements; ++e) breaks.push_back(breaks.back() + h), h *= 1.3;
  breaks.back() = length;
  return ss::KnotVector(degree, breaks);
}

// Each span split in two: the nested space of the next level.
ss::KnotVector bisected(const ss::KnotVector& k) {
  std::vector<double> breaks;
  for (std::size_t i = 0; i + 1 < k.breaks().size(); ++i) {
    breaks.push_back(k.breaks()[i]);
    breaks.push_back(0.5 * (k.breaks()[i] + k.breaks()[i + 1]));
  }
  breaks.push_back(k.breaks().back());
  return ss::KnotVector(k.degree(), breaks);
}

}  // namespace

TEST_CASE("spline shell: the basis is a partition of unity with derivatives summing to zero", "[spline_shell]") {
  for (int p = 2; p <= 4; ++p) {
    const ss::KnotVector k = graded(p, 0.7, 9);
    CHECK(k.basis_count() == 9 + p);
    for (int s = 0; s <= 200; ++s) {
      const double u = 0.7 * s / 200.0;
      const ss::KnotVector::Values v = k.evaluate(u, 2);
      INFO("degree " << p << " at u = " << u);
      CHECK(v.values.row(0).sum() == Approx(1.0).epsilon(1e-13));
      CHECK(std::abs(v.values.row(1).sum()) < 1e-9);
      CHECK(std::abs(v.values.row(2).sum()) < 1e-6);
      CHECK((v.values.row(0) >= -1e-15).all());
    }
  }
}

TEST_CASE("spline shell: controls at the Greville abscissae give the flat sheet exactly", "[spline_shell]") {
  const ss::SplinePatch patch(graded(3, 0.6, 7), graded(3, 0.45, 5));
  const ss::VecX x = patch.flat_positions();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(0.0, 0.6), V(0.0, 0.45);
  for (int s = 0; s < 50; ++s) {
    const ss::Vec2 uv(U(rng), V(rng));
    CHECK((patch.position(x, uv) - ss::Vec3(uv.x(), uv.y(), 0.0)).norm() < 1e-14);
    CHECK((patch.normal(x, uv) - ss::Vec3::UnitZ()).norm() < 1e-12);
    CHECK(patch.second_form(x, uv).norm() < 1e-10);
  }
}

TEST_CASE("spline shell: knot insertion represents the coarse surface exactly", "[spline_shell]") {
  for (int p = 2; p <= 3; ++p) {
    const ss::SplinePatch coarse(graded(p, 0.5, 4), graded(p, 0.4, 3));
    const ss::SplinePatch fine(bisected(coarse.u()), bisected(coarse.v()));
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n(0.0, 0.05);
    ss::VecX x = coarse.flat_positions();
    for (int i = 0; i < x.size(); ++i) x[i] += n(rng);
    const ss::VecX y = ss::refine_controls(coarse, x, fine);
    REQUIRE(y.size() == 3 * fine.control_count());
    std::uniform_real_distribution<double> U(0.0, 0.5), V(0.0, 0.4);
    double worst = 0, worst_form = 0;
    for (int s = 0; s < 100; ++s) {
      const ss::Vec2 uv(U(rng), V(rng));
      worst = std::max(worst, (coarse.position(x, uv) - fine.position(y, uv)).norm());
      worst_form = std::max(worst_form, (coarse.second_form(x, uv) - fine.second_form(y, uv)).norm());
    }
    INFO("degree " << p);
    CHECK(worst < 1e-13);
    CHECK(worst_form < 1e-9);
  }
  SECTION("a finer space that misses a coarse breakpoint is refused") {
    const ss::KnotVector a(3, {0.0, 0.3, 1.0}), b(3, {0.0, 0.5, 1.0});
    CHECK_THROWS_WITH(ss::prolongation(a, b), Catch::Contains("no breakpoint at 0.3"));
  }
}

TEST_CASE("spline shell: interpolation at the Greville abscissae reproduces a spline of the space", "[spline_shell]") {
  const ss::SplinePatch patch(graded(3, 0.5, 5), graded(3, 0.4, 4));
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 0.02);
  ss::VecX x = patch.flat_positions();
  for (int i = 0; i < x.size(); ++i) x[i] += n(rng);
  const ss::VecX y = patch.interpolate([&](const ss::Vec2& uv) { return patch.position(x, uv); });
  CHECK((x - y).lpNorm<Eigen::Infinity>() < 1e-12);
}

TEST_CASE("spline shell: the Gauss rule integrates polynomials of degree 2n - 1 exactly", "[spline_shell]") {
  for (int n = 1; n <= 6; ++n) {
    const ss::GaussRule rule = ss::gauss_legendre(n, 0.2, 0.9);
    for (int d = 0; d <= 2 * n - 1; ++d) {
      double sum = 0;
      for (int k = 0; k < n; ++k) sum += rule.weights[k] * std::pow(rule.points[k], d);
      const double exact = (std::pow(0.9, d + 1) - std::pow(0.2, d + 1)) / (d + 1);
      INFO(n << " points, degree " << d);
      CHECK(sum == Approx(exact).epsilon(1e-13));
    }
  }
}

TEST_CASE("spline shell: bad knot vectors are refused with what was expected", "[spline_shell]") {
  CHECK_THROWS_WITH(ss::KnotVector(1, {0.0, 1.0}), Catch::Contains("expected 2 to 4"));
  CHECK_THROWS_WITH(ss::KnotVector(3, {0.0}), Catch::Contains("at least two"));
  CHECK_THROWS_WITH(ss::KnotVector(3, {0.0, 0.5, 0.5, 1.0}), Catch::Contains("expected finite and increasing"));
  CHECK_THROWS_WITH(ss::KnotVector(3, {0.1, 1.0}), Catch::Contains("start at 0"));
  CHECK_THROWS_WITH(ss::SplinePatch(ss::KnotVector(2, {0.0, 1.0}), ss::KnotVector(3, {0.0, 1.0})),
                    Catch::Contains("expected equal"));
}

TEST_CASE("spline shell: a knot of multiplicity p - 1 leaves the basis C1 with a curvature jump", "[spline_shell]") {
  const ss::KnotVector k(3, {0.0, 0.1, 0.2, 0.35, 0.5}, {4, 1, 2, 1, 4});
  CHECK(k.basis_count() == 3 + 1 + 1 + 2 + 1);
  CHECK(k.first_basis(0) == 0);
  CHECK(k.first_basis(2) == 1 + 2);  // past the simple knot at 0.1 and the double one at 0.2
  const double eps = 1e-9;
  const ss::KnotVector::Values below = k.evaluate(0.2 - eps, 2), above = k.evaluate(0.2 + eps, 2);
  // Spread both onto all basis functions and compare value, slope and curvature across 0.2.
  Eigen::ArrayXXd b = Eigen::ArrayXXd::Zero(3, k.basis_count()), a = b;
  for (int m = 0; m <= 3; ++m) b.col(below.first + m) = below.values.col(m), a.col(above.first + m) = above.values.col(m);
  CHECK((a.row(0) - b.row(0)).abs().maxCoeff() < 1e-7);
  CHECK((a.row(1) - b.row(1)).abs().maxCoeff() < 1e-5);
  CHECK((a.row(2) - b.row(2)).abs().maxCoeff() > 1.0);  // second derivatives jump
  // The basis functions that reach into (0.2, 0.35): those of that span only.
  const auto [first, last] = k.basis_meeting(0.2, 0.35);
  CHECK(first == k.first_basis(2));
  CHECK(last == k.first_basis(2) + 3);
  CHECK_THROWS_WITH(ss::KnotVector(3, {0.0, 0.5, 1.0}, {1, 3, 1}), Catch::Contains("expected 1 to 2"));
}

TEST_CASE("spline shell: refinement keeps a jaw edge's multiplicity and stays nested", "[spline_shell]") {
  const ss::KnotVector coarse(3, {0.0, 0.1, 0.2, 0.35, 0.5}, {4, 1, 2, 1, 4});
  const ss::KnotVector fine = bisected(coarse);  // simple new knots, but the double one must stay
  CHECK_THROWS_WITH(ss::prolongation(coarse, fine), Catch::Contains("lower multiplicity"));
  const ss::KnotVector kept = ss::refined(coarse);
  CHECK(kept.element_count() == 8);
  CHECK(kept.basis_count() == coarse.basis_count() + 4);
  const Eigen::MatrixXd T = ss::prolongation(coarse, kept);
  // Every coarse basis function is a combination of the finer ones, exactly.
  for (int s = 0; s <= 100; ++s) {
    const double u = 0.5 * s / 100.0;
    const ss::KnotVector::Values c = coarse.evaluate(u, 0), f = kept.evaluate(u, 0);
    Eigen::VectorXd nc = Eigen::VectorXd::Zero(coarse.basis_count()), nf = Eigen::VectorXd::Zero(kept.basis_count());
    for (int m = 0; m <= 3; ++m) nc[c.first + m] = c.values(0, m), nf[f.first + m] = f.values(0, m);
    CHECK((T.transpose() * nf - nc).lpNorm<Eigen::Infinity>() < 1e-13);
  }
}
