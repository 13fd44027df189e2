#pragma once
// Numeric Cholesky factorisations on a worker thread, so that a solver can go on with an older
// factor (as a CG preconditioner) while a newer Hessian is factorised on the other core.
//
// Submitted matrices carry increasing tickets; only the newest is ever wanted, so a submission
// drops the older ones still waiting or finished (one being factorised runs to its end, and is
// then dropped unless it is the newest). take() hands over the factor of a ticket by swapping it
// with the caller's, so no factor is copied; the caller's old one is recycled. At most three
// factor objects exist: the caller's, one finished and one in progress. Factor
// objects are analysed (symbolically) for the current pattern on the worker, the first time
// each is used after reset(). The worker factorises serially (one core): see sparse_cholesky.cc.

#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "twin/solvers/sparse_cholesky.h"

namespace twin {

class BackgroundFactorizer {
 public:
  BackgroundFactorizer() = default;
  ~BackgroundFactorizer();  // waits for the factorisation in progress, then stops the worker
  BackgroundFactorizer(const BackgroundFactorizer&) = delete;
  BackgroundFactorizer& operator=(const BackgroundFactorizer&) = delete;

  // A new sparsity pattern (upper triangle): waits for the factorisation in progress and drops
  // every result and waiting submission of the old one.
  void reset(const HessianPattern::Matrix& upper);
  // Queues the factorisation of a copy of `upper` (reset()'s pattern) under `ticket`, which must
  // be greater than every earlier one, in place of any older one not started.
  void submit(const HessianPattern::Matrix& upper, long ticket);

  struct Taken {
    bool found = false;     // false: that ticket was never submitted since reset(), or taken
    bool ok = false;        // false: that matrix was not positive definite (factor left untouched)
    double waited_s = 0.0;  // how long take() blocked
  };
  // Waits for the factorisation of `ticket` and on success swaps it into `factor` (which must
  // be analysed for the current pattern, or null).
  Taken take(std::unique_ptr<SparseCholesky>& factor, long ticket);

 private:
  struct Result {
    long ticket = -1;
    bool ok = false;
    long pattern_id = -1;
    std::unique_ptr<SparseCholesky> factor;
  };
  void run();
  // A recycled factor object and the pattern id it was analysed for (-1: new); lock held.
  std::pair<std::unique_ptr<SparseCholesky>, long> spare_factor();

  std::mutex mutex_;
  std::condition_variable work_ready_, work_done_;
  std::thread worker_;
  bool stop_ = false;
  long busy_ticket_ = -1;  // being factorised, or -1
  long pattern_id_ = 0;
  std::unique_ptr<HessianPattern::Matrix> pattern_;  // values overwritten by each job
  std::deque<std::pair<long, std::vector<double>>> queue_;  // tickets and matrix values
  std::deque<Result> done_;  // oldest first
  std::vector<std::pair<std::unique_ptr<SparseCholesky>, long>> spares_;
};

}  // namespace twin
