#pragma once
// Cooperative cancellation of the twin's long computations: a cell's in-situ calibration runs
// identification for minutes in the background and must end promptly when the cell stops.
//
// A thread installs a flag with a CancellationScope; every Newton iteration run on that thread
// (newton_solver.cc), or on the lanes it starts (job_lanes.h hands the flag on), checks it and
// stops with SolveStatus::kCancelled once it is set. Callers see a failed solve, as for any other
// numerical trouble, and give up within one iteration. No flag installed: nothing is checked.
#include <atomic>

namespace twin {

class CancellationScope {
 public:
  // `flag` (may be null: nothing to check) must outlive the scope.
  explicit CancellationScope(const std::atomic<bool>* flag);
  ~CancellationScope();
  CancellationScope(const CancellationScope&) = delete;
  CancellationScope& operator=(const CancellationScope&) = delete;

 private:
  const std::atomic<bool>* previous_;
};

// The current thread's flag is installed and set.
bool cancellation_requested();
// The current thread's flag (null when none), for code that starts threads of its own.
const std::atomic<bool>* current_cancellation_flag();

}  // namespace twin
