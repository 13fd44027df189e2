#pragma once
// Sparsity pattern of the free-DOF Hessian and the scatter of element Hessians into it.
//
// The matrix is the upper triangle (row <= column) of the 3 nf x 3 nf Hessian over free
// vertices, in compressed-column form, as CHOLMOD's symmetric (stype = 1) input wants it. The
// pattern is built once per set of fixed vertices (it changes when a clamp grips or releases,
// not when clamps move), with a table that maps each element's 3x3 vertex-pair blocks straight
// to value slots, so assembly is a sequence of dense adds with no searching.

#include <vector>

#include <Eigen/SparseCore>

#include "twin/model/dof_map.h"
#include "twin/base/types.h"

namespace twin {

// The elements of one energy term: `arity` vertex ids per element.
struct TermStencil {
  int arity = 0;
  const std::vector<int>* element_vertices = nullptr;
};

class HessianPattern {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  HessianPattern(const DofMap& dofs, const std::vector<TermStencil>& terms);

  Matrix& matrix() { return matrix_; }
  const Matrix& matrix() const { return matrix_; }
  void set_zero();

  // Adds the dense Hessian h (3A x 3A, blocks in the element's vertex order) of element
  // `element` of term `term`. Entries of fixed vertices are dropped. Elements that share no
  // vertex may be added concurrently.
  template <int A>
  void add(int term, int element, const Eigen::Matrix<double, 3 * A, 3 * A>& h);

 private:
  static constexpr int pairs(int arity) { return arity * (arity + 1) / 2; }

  Matrix matrix_;
  // Per term, per element, per vertex pair (a <= b), per column k of the block: the value index
  // of the block's first row in that column, times 2, plus 1 when the stored block is the
  // transpose (the pair's free indices run backwards); -1 when a vertex is fixed.
  std::vector<std::vector<int>> slots_;
};

template <int A>
void HessianPattern::add(int term, int element, const Eigen::Matrix<double, 3 * A, 3 * A>& h) {
  const int* s = slots_[term].data() + static_cast<std::size_t>(element) * pairs(A) * 3;
  double* values = matrix_.valuePtr();
  for (int a = 0; a < A; ++a) {
    for (int b = a; b < A; ++b, s += 3) {
      if (s[0] < 0) continue;
      if (a == b) {
        for (int k = 0; k < 3; ++k) {
          double* col = values + (s[k] >> 1);
          for (int r = 0; r <= k; ++r) col[r] += h(3 * a + r, 3 * a + k);
        }
      } else if (!(s[0] & 1)) {
        for (int k = 0; k < 3; ++k) {
          double* col = values + (s[k] >> 1);
          for (int r = 0; r < 3; ++r) col[r] += h(3 * a + r, 3 * b + k);
        }
      } else {
        for (int k = 0; k < 3; ++k) {
          double* col = values + (s[k] >> 1);
          for (int r = 0; r < 3; ++r) col[r] += h(3 * b + r, 3 * a + k);
        }
      }
    }
  }
}

}  // namespace twin
