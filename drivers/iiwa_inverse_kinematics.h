#pragma once
// Inverse kinematics of an iiwa arm to a flange pose: damped least squares (Levenberg-Marquardt
// damping adapted to progress) from a seed configuration, every iterate clamped to the joint
// position limits, the redundant seventh degree of freedom used to stay near the seed. Never
// throws; the result says whether the pose was reached and, if not, how far off it stayed.

#include "drivers/iiwa_kinematics.h"

namespace drivers {

struct IkOptions {
  double position_tolerance_m = 1e-4;       // converged when the flange is this close ...
  double orientation_tolerance_rad = 1e-3;  // ... and turned at most this far from the target
  int max_iterations = 300;
  // Orientation error is weighted as if one radian were this many metres (balances the two).
  double orientation_weight_m = 0.2;
  double initial_damping = 1e-3;  // lambda^2 of the first step, in m^2 (weighted units)
  // A local method can stall against a joint limit when the seed is far from the solution
  // (measured from a fixed home seed: about 14 % of random reachable poses). When the seed does
  // not converge, up to `restarts` further seeds drawn uniformly within the limits (random
  // generator seeded with restart_seed, so results are repeatable) are tried; the first that
  // converges wins. 0 keeps the answer near the given seed (tracking); planning may use more.
  int restarts = 0;
  unsigned restart_seed = 1;
};

enum class IkStatus {
  kConverged,    // within tolerance, joints within limits
  kUnreachable,  // the closest configuration found misses the pose (see residuals)
  kJointLimit,   // stopped against a joint position limit short of the pose
};
const char* to_string(IkStatus status);

struct IkResult {
  IkStatus status = IkStatus::kUnreachable;
  JointVector q = JointVector::Zero();  // best configuration found (always within limits)
  double position_residual_m = 0;       // flange position error of q
  double orientation_residual_rad = 0;  // flange rotation error of q
  int iterations = 0;
  int limited_joint = -1;               // kJointLimit: a joint (0-based) at its limit
  int attempts = 1;                     // the seed plus the restarts used
};

// Solves for q with arm.flange_in_cell(q) = target (cell frame), starting from seed.
IkResult solve_inverse_kinematics(const IiwaArm& arm, const Eigen::Isometry3d& target,
                                  const JointVector& seed, const IkOptions& options = {});

}  // namespace drivers
