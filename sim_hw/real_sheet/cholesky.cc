#include "sim_hw/real_sheet/cholesky.h"

#include <cstring>
#include <mutex>
#include <stdexcept>

#include <cholmod.h>
#include <dlfcn.h>
#include <omp.h>

namespace sim_hw::real_sheet {

namespace {

// A plate's supernodes are too small to gain from BLAS threads, and on two cores OpenBLAS's
// spinning threads and CHOLMOD's fixed OpenMP loops slow its factorisation several times; a
// fine spline shell's separators are dense blocks of a thousand columns and more, which BLAS
// threads do speed up (2 threads: 2.2 -> 1.6 s for 114k unknowns). So the BLAS runs on one
// thread, and on the OpenMP threads for a factorisation of at least kThreadedFlops. The BLAS
// is a run-time choice (libblas.so.3), so OpenBLAS's setter is looked up, not linked.
constexpr double kThreadedFlops = 2e9;

void set_blas_threads(int threads) {
  using SetThreads = void (*)(int);
  static const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(threads);
}

void single_threaded_blas() {
  static std::once_flag once;
  std::call_once(once, [] { set_blas_threads(1); });
}

}  // namespace

struct Cholesky::State {
  cholmod_common common;
  cholmod_sparse* A = nullptr;
  cholmod_factor* L = nullptr;
  std::uint64_t pattern = 0;  // the pattern L was analysed for
  bool usable = false;
  double flops = 0;  // of the numeric factorisation, from the analysis
};

Cholesky::Cholesky() : state_(std::make_unique<State>()) {
  cholmod_start(&state_->common);
  state_->common.print = 0;
  state_->common.error_handler = nullptr;
  state_->common.quick_return_if_not_posdef = 1;
  // Nested dissection: less fill than AMD on a grid; analysed once per pattern. CHOLMOD's own,
  // not METIS_NodeND, which swaps the process's SIGTERM handler for its own while it runs
  // (twin/solvers/sparse_cholesky.cc says what that did to a process stopped by a signal).
  state_->common.nmethods = 1;
  state_->common.method[0].ordering = CHOLMOD_NESDIS;
  single_threaded_blas();
}

Cholesky::~Cholesky() {
  if (state_->L) cholmod_free_factor(&state_->L, &state_->common);
  if (state_->A) cholmod_free_sparse(&state_->A, &state_->common);
  cholmod_finish(&state_->common);
}

bool Cholesky::factorize(const BlockSparseMatrix& M) {
  State& s = *state_;
  const int n = M.size();
  const long nnz = static_cast<long>(M.values().size());
  const bool same_pattern = s.A && s.pattern == M.pattern_id();
  if (!same_pattern) {
    if (s.L) cholmod_free_factor(&s.L, &s.common);
    if (s.A) cholmod_free_sparse(&s.A, &s.common);
    s.A = cholmod_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_REAL, &s.common);
    if (!s.A) throw std::runtime_error("real sheet: CHOLMOD could not allocate the Hessian");
    std::memcpy(s.A->p, M.column_starts().data(), sizeof(int) * (n + 1));
    std::memcpy(s.A->i, M.row_indices().data(), sizeof(int) * nnz);
    s.L = cholmod_analyze(s.A, &s.common);
    if (!s.L) throw std::runtime_error("real sheet: CHOLMOD could not analyse the Hessian");
    s.pattern = M.pattern_id();
    s.flops = s.common.fl;
  }
  std::memcpy(s.A->x, M.values().data(), sizeof(double) * nnz);
  // No nested OpenMP level on this thread: CHOLMOD's small parallel loops then run serially.
  struct SerialNesting {
    const int saved = omp_get_max_active_levels();
    SerialNesting() { omp_set_max_active_levels(0); }
    ~SerialNesting() { omp_set_max_active_levels(saved); }
  } serial;
  const bool threaded = s.flops >= kThreadedFlops && omp_get_max_threads() > 1;
  if (threaded) set_blas_threads(omp_get_max_threads());
  cholmod_factorize(s.A, s.L, &s.common);
  if (threaded) set_blas_threads(1);
  s.usable = s.common.status == CHOLMOD_OK && s.L->minor == static_cast<std::size_t>(n);
  return s.usable;
}

Eigen::VectorXd Cholesky::solve(const Eigen::VectorXd& b) const {
  State& s = *state_;
  if (!s.usable) throw std::logic_error("real sheet: solve without a usable factorisation");
  cholmod_dense B;
  B.nrow = b.size();
  B.ncol = 1;
  B.nzmax = b.size();
  B.d = b.size();
  B.x = const_cast<double*>(b.data());
  B.z = nullptr;
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, s.L, &B, &s.common);
  if (!X) throw std::runtime_error("real sheet: CHOLMOD solve failed");
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(X->x), b.size());
  cholmod_free_dense(&X, &s.common);
  return x;
}

}  // namespace sim_hw::real_sheet
