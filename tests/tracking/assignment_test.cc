#include "tracking/assignment.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace tracking {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Exhaustive reference: the most allowed pairs, then the least cost, over every injective map of
// the smaller side into the larger (rows <= 7 keeps this under a few thousand maps).
struct Best {
  int pairs = -1;
  double cost = kInf;
};

Best brute_force(const Eigen::MatrixXd& cost) {
  const bool transpose = cost.rows() > cost.cols();
  const Eigen::MatrixXd c = transpose ? Eigen::MatrixXd(cost.transpose()) : cost;
  std::vector<int> columns(c.cols());
  std::iota(columns.begin(), columns.end(), 0);
  Best best;
  // Every permutation of the columns; row i takes columns[i] (rows <= columns).
  do {
    int pairs = 0;
    double total = 0.0;
    for (int i = 0; i < c.rows(); ++i) {
      const double x = c(i, columns[i]);
      if (std::isfinite(x)) {
        ++pairs;
        total += x;
      }
    }
    if (pairs > best.pairs || (pairs == best.pairs && total < best.cost)) best = {pairs, total};
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

void check_consistent(const Eigen::MatrixXd& cost, const Assignment& a) {
  REQUIRE(a.column_of_row.size() == static_cast<std::size_t>(cost.rows()));
  REQUIRE(a.row_of_column.size() == static_cast<std::size_t>(cost.cols()));
  int pairs = 0;
  double total = 0.0;
  for (int i = 0; i < cost.rows(); ++i) {
    const int j = a.column_of_row[i];
    if (j < 0) continue;
    REQUIRE(a.row_of_column[j] == i);
    REQUIRE(std::isfinite(cost(i, j)));  // never a forbidden pair
    ++pairs;
    total += cost(i, j);
  }
  CHECK(pairs == a.assigned_count);
  CHECK(total == Approx(a.total_cost));
}

TEST_CASE("assignment: the hand-made case where greedy nearest fails", "[assignment]") {
  // Rows A, B; columns x, y. The cheapest pair is A-x (1), but taking it forces B-y (10):
  // total 11. A-y + B-x costs 2 + 3 = 5.
  Eigen::MatrixXd cost(2, 2);
  cost << 1, 2,
          3, 10;
  const Assignment a = solve_assignment(cost);
  CHECK(a.column_of_row == std::vector<int>{1, 0});
  CHECK(a.total_cost == 5);
  check_consistent(cost, a);
}

TEST_CASE("assignment: more pairs beat less cost, and forbidden pairs are never used",
          "[assignment]") {
  // Greedy takes B-x (0.45); then A may only have x, so A stays alone and y too. Pairing A-x and
  // B-y costs more but finds both.
  Eigen::MatrixXd cost(2, 2);
  cost << 0.55, kInf,
          0.45, 0.9;
  const Assignment a = solve_assignment(cost);
  CHECK(a.column_of_row == std::vector<int>{0, 1});
  CHECK(a.assigned_count == 2);

  Eigen::MatrixXd none(2, 3);
  none.setConstant(kInf);
  const Assignment b = solve_assignment(none);
  CHECK(b.assigned_count == 0);
  CHECK(b.column_of_row == std::vector<int>{-1, -1});
  CHECK(b.row_of_column == std::vector<int>{-1, -1, -1});
}

TEST_CASE("assignment: empty and degenerate inputs", "[assignment]") {
  CHECK(solve_assignment(Eigen::MatrixXd(0, 4)).row_of_column == std::vector<int>(4, -1));
  CHECK(solve_assignment(Eigen::MatrixXd(3, 0)).column_of_row == std::vector<int>(3, -1));
  Eigen::MatrixXd zeros = Eigen::MatrixXd::Zero(3, 3);
  CHECK(solve_assignment(zeros).assigned_count == 3);
  Eigen::MatrixXd negative = Eigen::MatrixXd::Ones(2, 2);
  negative(1, 0) = -1.0;
  CHECK_THROWS_AS(solve_assignment(negative), std::invalid_argument);
  Eigen::MatrixXd with_nan = Eigen::MatrixXd::Ones(2, 2);
  with_nan(0, 0) = std::nan("");  // NaN forbids, like infinity
  const Assignment a = solve_assignment(with_nan);
  CHECK(a.column_of_row == std::vector<int>{1, 0});
}

TEST_CASE("assignment: optimal against exhaustive search on random rectangular problems",
          "[assignment]") {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> size(1, 6);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const int rows = size(rng), cols = size(rng);
    Eigen::MatrixXd cost(rows, cols);
    // About a third forbidden, and coarse values so that ties happen too.
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) {
        cost(i, j) = value(rng) < 0.35 ? kInf : std::round(10.0 * value(rng)) * 1e-4;
      }
    }
    INFO("trial " << trial << "\n" << cost);
    const Assignment a = solve_assignment(cost);
    check_consistent(cost, a);
    const Best best = brute_force(cost);
    CHECK(a.assigned_count == best.pairs);
    CHECK(a.total_cost == Approx(best.cost).margin(1e-12));
  }
}

TEST_CASE("assignment: a 289 x 300 problem with a known optimum", "[assignment]") {
  // Each row has one cheap column (a permutation); every other allowed pair costs more. The
  // optimum is the permutation, whatever the order of rows and columns.
  const int rows = 289, cols = 300;
  std::mt19937 rng(12);
  std::vector<int> truth(cols);
  std::iota(truth.begin(), truth.end(), 0);
  std::shuffle(truth.begin(), truth.end(), rng);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  Eigen::MatrixXd cost(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) cost(i, j) = value(rng) < 0.9 ? kInf : 1.0 + value(rng);
    cost(i, truth[i]) = 0.5 * value(rng);
  }
  const Assignment a = solve_assignment(cost);
  check_consistent(cost, a);
  for (int i = 0; i < rows; ++i) CHECK(a.column_of_row[i] == truth[i]);
}

}  // namespace
}  // namespace tracking
