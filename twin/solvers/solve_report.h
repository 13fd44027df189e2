#pragma once
// What a solve did: whether its result may be used, why it stopped, and what it cost.
// Solvers return this instead of throwing; a result that is not usable is never written back.

#include <string>

namespace twin {

enum class SolveStatus {
  kConverged,           // residual below tolerance: the result is an equilibrium / a valid step
  kIterationBudget,     // a fixed-iteration solve (a linearised implicit step) that lowered its
                        // objective with finite forces: usable by that scheme's definition
  kMaxIterations,       // no convergence within the iteration budget
  kLineSearchFailed,    // no step decreased the energy (stagnation or a broken model)
  kNonFinite,           // NaN or infinity in energy or forces (diverged or degenerate triangle)
  kIndefinite,          // no positive-definite system even after shifting
  kBlowUp,              // a dynamic step produced implausible velocities
  kCancelled,           // the caller asked to stop (twin/base/cancellation.h)
};

const char* to_string(SolveStatus status);

struct SolveReport {
  SolveStatus status = SolveStatus::kMaxIterations;
  int iterations = 0;        // Newton iterations
  int factorizations = 0;    // numeric Cholesky factorisations (shifted retries included) the
                             // solve computed or waited for
  int cg_iterations = 0;     // with a reused factor (newton_linear_solver.h)
  int fallbacks = 0;         // solves whose CG missed its tolerance and waited for a new factor
  double factor_wait_s = 0.0;  // spent waiting for background factorisations (in `seconds`)
  double residual = 0.0;     // ||free force|| / force scale at the last iterate (on failure x
                             // is back at its start, not at that iterate)
  double energy_J = 0.0;
  double seconds = 0.0;
  std::string message;

  // This solve followed by `later` (a retry, a fallback, the next phase): costs add up, the
  // outcome is later's.
  void append(const SolveReport& later) {
    iterations += later.iterations;
    factorizations += later.factorizations;
    cg_iterations += later.cg_iterations;
    fallbacks += later.fallbacks;
    factor_wait_s += later.factor_wait_s;
    seconds += later.seconds;
    status = later.status;
    residual = later.residual;
    energy_J = later.energy_J;
    message = later.message;
  }

  bool usable() const {
    return status == SolveStatus::kConverged || status == SolveStatus::kIterationBudget;
  }
  std::string brief() const;
};

}  // namespace twin
