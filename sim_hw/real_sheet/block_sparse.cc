#include "sim_hw/real_sheet/block_sparse.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>

namespace sim_hw::real_sheet {

BlockSparseMatrix::BlockSparseMatrix(int blocks, const std::vector<std::vector<int>>& groups)
    : blocks_(blocks), upper_(blocks) {
  for (int b = 0; b < blocks; ++b) upper_[b].push_back(b);
  for (const auto& group : groups) {
    for (int a : group) {
      for (int b : group) {
        if (a < b) upper_[b].push_back(a);
      }
    }
  }
  for (auto& rows : upper_) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  // Column 3b + j: three rows per block a < b, then rows 3b .. 3b + j.
  starts_.assign(3 * blocks + 1, 0);
  for (int b = 0; b < blocks; ++b) {
    const int off = 3 * (static_cast<int>(upper_[b].size()) - 1);
    for (int j = 0; j < 3; ++j) starts_[3 * b + j + 1] = starts_[3 * b + j] + off + j + 1;
  }
  rows_.resize(starts_.back());
  for (int b = 0; b < blocks; ++b) {
    for (int j = 0; j < 3; ++j) {
      int k = starts_[3 * b + j];
      for (int a : upper_[b]) {
        for (int i = 0; i < 3 && (a < b || i <= j); ++i) rows_[k++] = 3 * a + i;
      }
    }
  }
  values_.assign(rows_.size(), 0.0);
  static std::atomic<std::uint64_t> patterns{0};
  pattern_id_ = ++patterns;
}

void BlockSparseMatrix::set_zero() { std::fill(values_.begin(), values_.end(), 0.0); }

int BlockSparseMatrix::entry(int a, int b) const {
  const auto& rows = upper_[b];
  const auto it = std::lower_bound(rows.begin(), rows.end(), a);
  if (it == rows.end() || *it != a) throw std::logic_error("block sparse matrix: block pair outside the pattern");
  return 3 * static_cast<int>(it - rows.begin());
}

void BlockSparseMatrix::add(const int* blocks, int n, const Eigen::Ref<const Eigen::MatrixXd>& H) {
  for (int p = 0; p < n; ++p) {
    for (int q = 0; q < n; ++q) {
      const int a = blocks[p], b = blocks[q];
      if (a > b) continue;
      const int offset = entry(a, b);
      for (int j = 0; j < 3; ++j) {
        double* column = &values_[starts_[3 * b + j] + offset];
        for (int i = 0; i < 3 && (a < b || i <= j); ++i) column[i] += H(3 * p + i, 3 * q + j);
      }
    }
  }
}

void BlockSparseMatrix::add_to_diagonal(const Eigen::VectorXd& d) {
  // The diagonal entry of column c is its last.
  for (int c = 0; c < size(); ++c) values_[starts_[c + 1] - 1] += d[c];
}

void BlockSparseMatrix::fix_blocks(const std::vector<char>& fixed) {
  for (int c = 0; c < size(); ++c) {
    for (int k = starts_[c]; k < starts_[c + 1]; ++k) {
      const int r = rows_[k];
      if (fixed[r / 3] || fixed[c / 3]) values_[k] = r == c ? 1.0 : 0.0;
    }
  }
}

Eigen::MatrixXd BlockSparseMatrix::dense() const {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size(), size());
  for (int c = 0; c < size(); ++c) {
    for (int k = starts_[c]; k < starts_[c + 1]; ++k) M(rows_[k], c) = M(c, rows_[k]) = values_[k];
  }
  return M;
}

}  // namespace sim_hw::real_sheet
