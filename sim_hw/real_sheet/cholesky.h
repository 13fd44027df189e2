#pragma once
// Sparse Cholesky of a BlockSparseMatrix by CHOLMOD (supernodal; the fill-reducing ordering is
// CHOLMOD's own choice, analysed once per pattern).

#include <memory>

#include <Eigen/Core>

#include "sim_hw/real_sheet/block_sparse.h"

namespace sim_hw::real_sheet {

class Cholesky {
 public:
  Cholesky();
  ~Cholesky();
  Cholesky(const Cholesky&) = delete;
  Cholesky& operator=(const Cholesky&) = delete;

  // False when the matrix is not positive definite (nothing usable is kept then).
  bool factorize(const BlockSparseMatrix& A);
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace sim_hw::real_sheet
