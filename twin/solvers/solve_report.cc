#include "twin/solvers/solve_report.h"

#include <fmt/format.h>

namespace twin {

const char* to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::kConverged: return "converged";
    case SolveStatus::kIterationBudget: return "iteration budget used (accepted)";
    case SolveStatus::kMaxIterations: return "no convergence within the iteration limit";
    case SolveStatus::kLineSearchFailed: return "line search failed";
    case SolveStatus::kNonFinite: return "non-finite energy or force";
    case SolveStatus::kIndefinite: return "system not positive definite after shifting";
    case SolveStatus::kBlowUp: return "velocity blow-up";
    case SolveStatus::kCancelled: return "cancelled";
  }
  return "unknown";
}

std::string SolveReport::brief() const {
  return fmt::format("{} after {} iterations ({} factorizations), residual {:.2e}, {:.1f} ms{}{}",
                     to_string(status), iterations, factorizations, residual, 1e3 * seconds,
                     message.empty() ? "" : ": ", message);
}

}  // namespace twin
