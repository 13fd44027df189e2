#pragma once
// Sparse Cholesky factorisation of the free-DOF Hessian with CHOLMOD (supernodal, through
// Eigen's CholmodSupport). The symbolic analysis (fill-reducing ordering, supernode structure)
// is done once per sparsity pattern; each Newton iteration only refactorises numerically.

#include <memory>

#include "twin/model/hessian_pattern.h"

namespace twin {

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Symbolic analysis of the pattern of `upper` (upper triangle of a symmetric matrix).
  void analyze(const HessianPattern::Matrix& upper);
  // Numeric factorisation of upper + shift * I. False if the matrix is not positive definite.
  bool factorize(const HessianPattern::Matrix& upper, double shift = 0.0);
  VecX solve(const VecX& rhs) const;
  bool analyzed() const { return analyzed_; }
  // From the symbolic analysis: floating-point operations of one numeric factorisation, and
  // non-zeros of the factor (one triangular solve streams them twice).
  double factor_flops() const;
  double factor_nonzeros() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool analyzed_ = false;
};

}  // namespace twin
