#include "twin/solvers/sparse_cholesky.h"

#include <dlfcn.h>
#include <omp.h>

#include <mutex>

#include <Eigen/CholmodSupport>

namespace twin {

namespace {

// OpenBLAS's worker threads wait by yielding in a loop; on 2 cores they fight the element loops'
// OpenMP threads and the supernodes of a sheet are too small to gain from them (measured: one
// BLAS thread factorises a 6k-triangle sheet as fast as two). libblas.so.3 is a run-time choice
// (OpenBLAS or the reference BLAS), so the call is looked up, not linked.
// Once per process: factorisations are built concurrently on the lanes of job_lanes.h, and
// OpenBLAS's setter reconfigures its thread pool.
void use_single_threaded_blas() {
  static std::once_flag once;
  std::call_once(once, [] {
    using SetThreads = void (*)(int);
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) {
      set(1);
    }
  });
}

}  // namespace

struct SparseCholesky::Impl {
  Eigen::CholmodSupernodalLLT<HessianPattern::Matrix, Eigen::Upper> llt;
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {
  cholmod_common& common = impl_->llt.cholmod();
  // "Not positive definite" is an expected answer here (the solver then shifts the matrix),
  // not something to print to stderr.
  common.print = 0;
  // Nested dissection gives less fill than AMD on sheet meshes; the analysis is slower but done
  // once per sparsity pattern. CHOLMOD's own (NESDIS), not METIS_NodeND (CHOLMOD_METIS): for the
  // whole of each call METIS_NodeND replaces the process's SIGTERM and SIGABRT handlers with
  // one that longjmps to the calling thread's jump buffer (GKlib's gk_sigtrap). In a process
  // whose other threads factorise, a SIGTERM in that window ran METIS's handler on the main
  // thread, which has no jump buffer: cell_controller died with SIGSEGV in ____longjmp_chk
  // instead of stopping. NESDIS asks METIS only for separators (METIS_ComputeVertexSeparator,
  // which traps nothing), and gives as little fill (twin_solver_limits prints both).
  // tests/twin/solvers/sparse_cholesky_signals_test.cc checks that an analysis leaves the
  // handlers alone.
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_NESDIS;
  use_single_threaded_blas();
}

SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::analyze(const HessianPattern::Matrix& upper) {
  impl_->llt.analyzePattern(upper);
  analyzed_ = true;
}

bool SparseCholesky::factorize(const HessianPattern::Matrix& upper, double shift) {
  impl_->llt.setShift(shift);
  // Debian's CHOLMOD is built to run small OpenMP loops with a fixed 4 threads inside the
  // supernodal factorisation; on a 2-core machine the resulting thread churn makes it 3-4x
  // slower (measured 85 ms vs 18-25 ms for a 6k-triangle sheet). With no active parallel level
  // allowed on this thread those loops run serially, while BLAS keeps its own threads. The limit
  // is this thread's own (a per-task ICV since OpenMP 5.0, as libgomp keeps it), so element loops
  // elsewhere are untouched. It replaced a two-thread region around the call, whose idle second
  // thread spun at the barrier for the whole factorisation: a core's worth of CPU taken from the
  // cell's tracker on every twin step (measured on the 6k benchmark sheet's static solve and 30
  // steps: 9.2 -> 6.3 s of CPU at the same wall time).
  struct SerialNesting {
    const int saved = omp_get_max_active_levels();
    SerialNesting() { omp_set_max_active_levels(0); }
    ~SerialNesting() { omp_set_max_active_levels(saved); }  // also when factorize throws
  } serial;
  impl_->llt.factorize(upper);
  return impl_->llt.info() == Eigen::Success;
}

double SparseCholesky::factor_flops() const { return impl_->llt.cholmod().fl; }
double SparseCholesky::factor_nonzeros() const { return impl_->llt.cholmod().lnz; }

VecX SparseCholesky::solve(const VecX& rhs) const { return impl_->llt.solve(rhs); }

}  // namespace twin
