#pragma once
// Quasi-static continuation: moves clamps from one set of poses to another in small increments,
// re-solving static equilibrium after each, starting every solve from the previous equilibrium.
// A hanging sheet has several equilibria (it can fold one way or the other); following the
// motion the clamps really made selects the one the real sheet reached.
//
// Order within one move: clamps that release let go first (the sheet settles at the remaining
// clamps), then all engaged clamps travel together along straight lines (rotations by slerp).
// A clamp that engages grips the material where it currently is and travels from there. When an
// increment fails to converge it is halved (down to 1/64 of the nominal increment) before the
// move is declared failed; a failed move leaves x as it was before the move.

#include "twin/solvers/static_solver.h"

namespace twin {

struct ContinuationOptions {
  double increment_m = 0.02;      // largest clamp travel per increment
  double increment_rad = 0.1;     // largest clamp rotation per increment
  NewtonOptions newton = default_static_options();
};

struct ContinuationReport {
  SolveReport last;               // the final equilibrium solve (or the one that failed)
  int increments = 0;             // equilibrium solves that converged
  int newton_iterations = 0;      // over all increments
  int factorizations = 0;
  double seconds = 0.0;
  bool usable() const { return last.usable(); }
  std::string brief() const;
};

class QuasiStaticSolver {
 public:
  QuasiStaticSolver(const ShellModel& model, const ClampSet& clamps);

  // x: an equilibrium for `from` (or any start, such as the flat sheet). On success x is the
  // equilibrium for `to`; on failure x is unchanged.
  ContinuationReport move(const std::vector<ClampPose>& from, const std::vector<ClampPose>& to,
                          VecX& x, const ContinuationOptions& options = {});

 private:
  const ClampSet& clamps_;
  StaticSolver statics_;
};

}  // namespace twin
