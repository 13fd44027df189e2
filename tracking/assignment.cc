#include "tracking/assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tracking {
namespace {

// Square-or-wide problem (rows <= columns, every cost finite): assigns every row. Returns the
// column of each row.
//
// Invariant: with potentials u (rows) and v (columns), every reduced cost
// cost(i, j) - u(i) - v(j) is >= 0 and is 0 on assigned pairs, which makes the current partial
// assignment optimal for the rows it covers. Each new row is added by a Dijkstra-like search
// over reduced costs for the cheapest alternating path to a free column; the potentials are
// updated on the way so the invariant holds after flipping the path.
std::vector<int> assign_all_rows(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  const double inf = std::numeric_limits<double>::infinity();
  // Index 0 of the column arrays is a virtual column that holds the row being inserted, which
  // keeps the path bookkeeping free of special cases; real columns are 1..cols.
  std::vector<double> u(rows + 1, 0.0), v(cols + 1, 0.0);
  std::vector<int> row_at(cols + 1, -1);  // row assigned to column j (-1 none)
  std::vector<int> previous_column(cols + 1, 0);
  std::vector<double> path_cost(cols + 1);
  std::vector<char> in_tree(cols + 1);

  for (int new_row = 0; new_row < rows; ++new_row) {
    row_at[0] = new_row;
    int column = 0;
    std::fill(path_cost.begin(), path_cost.end(), inf);
    std::fill(in_tree.begin(), in_tree.end(), 0);
    // Grow the shortest-path tree one column at a time until it reaches a free column.
    while (row_at[column] != -1) {
      in_tree[column] = 1;
      const int row = row_at[column];
      double step = inf;
      int next = -1;
      for (int j = 1; j <= cols; ++j) {
        if (in_tree[j]) continue;
        const double reduced = cost(row, j - 1) - u[row] - v[j];
        if (reduced < path_cost[j]) {
          path_cost[j] = reduced;
          previous_column[j] = column;
        }
        if (path_cost[j] < step) {
          step = path_cost[j];
          next = j;
        }
      }
      // Shift the potentials by the length of the newest tree edge: rows and columns in the
      // tree keep zero reduced cost on their tree edges, the others get closer by `step`.
      for (int j = 0; j <= cols; ++j) {
        if (in_tree[j]) {
          u[row_at[j]] += step;
          v[j] -= step;
        } else {
          path_cost[j] -= step;
        }
      }
      column = next;
    }
    // Flip the alternating path back to the virtual column: each column on it takes the row of
    // its predecessor.
    while (column != 0) {
      const int before = previous_column[column];
      row_at[column] = row_at[before];
      column = before;
    }
  }

  std::vector<int> column_of_row(rows, -1);
  for (int j = 1; j <= cols; ++j) {
    if (row_at[j] >= 0) column_of_row[row_at[j]] = j - 1;
  }
  return column_of_row;
}

}  // namespace

Assignment solve_assignment(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  Assignment result;
  result.column_of_row.assign(rows, -1);
  result.row_of_column.assign(cols, -1);
  if (rows == 0 || cols == 0) return result;

  // Forbidden pairs get a finite penalty larger than any total of allowed costs, so an optimal
  // solution of the padded problem uses as few of them as possible (most allowed pairs) and then
  // the least allowed cost; the penalised pairs are dropped afterwards.
  double largest_allowed = 0.0;
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const double c = cost(i, j);
      if (c < 0.0) throw std::invalid_argument("solve_assignment: negative cost");
      if (std::isfinite(c)) largest_allowed = std::max(largest_allowed, c);
    }
  }
  const int pairs = std::min(rows, cols);
  const double forbidden = (largest_allowed > 0.0 ? largest_allowed : 1.0) * (pairs + 1);
  const bool transpose = rows > cols;  // the solver wants rows <= columns
  Eigen::MatrixXd padded = transpose ? Eigen::MatrixXd(cost.transpose()) : cost;
  for (Eigen::Index i = 0; i < padded.rows(); ++i) {
    for (Eigen::Index j = 0; j < padded.cols(); ++j) {
      if (!std::isfinite(padded(i, j))) padded(i, j) = forbidden;
    }
  }

  const std::vector<int> solved = assign_all_rows(padded);
  for (int k = 0; k < static_cast<int>(solved.size()); ++k) {
    const int i = transpose ? solved[k] : k;
    const int j = transpose ? k : solved[k];
    if (!std::isfinite(cost(i, j))) continue;
    result.column_of_row[i] = j;
    result.row_of_column[j] = i;
    ++result.assigned_count;
    result.total_cost += cost(i, j);
  }
  return result;
}

}  // namespace tracking
