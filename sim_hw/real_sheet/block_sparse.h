#pragma once
// The symmetric Hessian of the independent sheet as CHOLMOD takes it: compressed columns, upper
// triangle, unknowns in blocks of three (a grid node's x, y, z, or a pivot jaw's rotation).
// The pattern is fixed at construction from groups of blocks that couple (a cell, a bending
// stencil, a jaw pad); values are then added block-wise, with a binary search per block pair.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace sim_hw::real_sheet {

class BlockSparseMatrix {
 public:
  BlockSparseMatrix() = default;
  // Every pair of blocks within one group couples. Blocks are 0 .. blocks - 1.
  BlockSparseMatrix(int blocks, const std::vector<std::vector<int>>& groups);

  int size() const { return 3 * blocks_; }
  void set_zero();
  // Adds H (3n x 3n, over `blocks` in that order; symmetric, only what falls in the upper
  // triangle is read) into the matrix. The blocks must belong to one group of the pattern.
  void add(const int* blocks, int n, const Eigen::Ref<const Eigen::MatrixXd>& H);
  void add(const std::vector<int>& blocks, const Eigen::Ref<const Eigen::MatrixXd>& H) {
    add(blocks.data(), static_cast<int>(blocks.size()), H);
  }
  void add_to_diagonal(const Eigen::VectorXd& d);
  // Rows and columns of the blocks marked fixed become those of the identity: a Newton step
  // then leaves those unknowns where they are (their gradient must be zeroed alongside).
  void fix_blocks(const std::vector<char>& fixed);

  const std::vector<int>& column_starts() const { return starts_; }
  const std::vector<int>& row_indices() const { return rows_; }
  const std::vector<double>& values() const { return values_; }
  Eigen::MatrixXd dense() const;  // for tests
  // Distinct for every pattern built (a factorisation's analysis is kept while it matches).
  std::uint64_t pattern_id() const { return pattern_id_; }

 private:
  int entry(int row_block, int col_block) const;  // index of the first entry of block column 0
  int blocks_ = 0;
  std::vector<std::vector<int>> upper_;  // per column block, the row blocks <= it, sorted
  std::vector<int> starts_, rows_;
  std::vector<double> values_;
  std::uint64_t pattern_id_ = 0;
};

}  // namespace sim_hw::real_sheet
