#pragma once
// Minimum-cost one-to-one assignment between the rows and columns of a rectangular cost matrix
// (rows: manifest markers, columns: scan candidates, in marker matching), where some pairs are
// not allowed. Shortest-augmenting-path Hungarian method with row and column potentials
// (Kuhn-Munkres in the Jonker-Volgenant formulation): O(r^2 c) for r <= c, about 25 M steps
// for 289 markers and 300 candidates.

#include <Eigen/Core>
#include <vector>

namespace tracking {

struct Assignment {
  std::vector<int> column_of_row;  // -1: row left unassigned
  std::vector<int> row_of_column;  // -1: column left unassigned
  int assigned_count = 0;
  double total_cost = 0.0;         // over the assigned pairs only
};

// `cost(i, j)` >= 0 is the cost of pairing row i with column j; +infinity (or NaN) forbids the
// pair. Among the assignments that use only allowed pairs, returns one with the most pairs and,
// among those, the least total cost. (Maximising the pairs first is what the matching needs: a
// pair inside the gate is a marker found, and leaving it out to save distance elsewhere would
// report a seen marker as missing.) Throws std::invalid_argument for a negative cost.
Assignment solve_assignment(const Eigen::MatrixXd& cost);

}  // namespace tracking
