#include "drivers/iiwa_inverse_kinematics.h"

#include <cmath>
#include <random>

namespace drivers {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Pose error target - current: position (m) and rotation vector (rad), both in the cell frame.
Vector6d pose_error(const Eigen::Isometry3d& current, const Eigen::Isometry3d& target) {
  Vector6d e;
  e.head<3>() = target.translation() - current.translation();
  const Eigen::AngleAxisd rotation(target.linear() * current.linear().transpose());
  e.tail<3>() = rotation.angle() * rotation.axis();
  return e;
}

// Weighted squared error: orientation scaled to metres so both parts count alike.
double cost(const Vector6d& e, double orientation_weight_m) {
  return e.head<3>().squaredNorm() + orientation_weight_m * orientation_weight_m *
                                         e.tail<3>().squaredNorm();
}

}  // namespace

const char* to_string(IkStatus status) {
  switch (status) {
    case IkStatus::kConverged: return "converged";
    case IkStatus::kUnreachable: return "unreachable";
    case IkStatus::kJointLimit: return "joint limit";
  }
  return "?";
}

namespace {

// One damped least-squares descent from `seed`.
IkResult descend(const IiwaArm& arm, const Eigen::Isometry3d& target, const JointVector& seed,
                 const IkOptions& options) {
  const IiwaParameters& p = arm.parameters();
  const double w = options.orientation_weight_m;
  Eigen::Matrix<double, 6, 1> weights;
  weights << 1, 1, 1, w, w, w;

  JointVector q = arm.clamp_to_limits(seed);
  Vector6d e = pose_error(arm.flange_in_cell(q), target);
  double c = cost(e, w);
  double damping = options.initial_damping;
  IkResult result;
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    if (e.head<3>().norm() <= options.position_tolerance_m &&
        e.tail<3>().norm() <= options.orientation_tolerance_rad) {
      break;
    }
    IiwaJacobian j = weights.asDiagonal() * arm.jacobian(q);
    const Vector6d we = weights.asDiagonal() * e;
    // dq = J^T (J J^T + lambda^2 I)^-1 e: the minimum-norm step, so the redundant joint stays
    // near the seed; lambda keeps steps bounded near singularities. A joint on a limit that the
    // step would push further out is frozen (its column removed) and the step recomputed, so
    // the other joints make up for it instead of the clamp undoing the step.
    JointVector dq = JointVector::Zero();
    for (int pass = 0; pass < kIiwaJoints; ++pass) {
      const Eigen::Matrix<double, 6, 6> jjt =
          j * j.transpose() + damping * Eigen::Matrix<double, 6, 6>::Identity();
      dq = j.transpose() * jjt.ldlt().solve(we);
      bool froze = false;
      for (int i = 0; i < kIiwaJoints; ++i) {
        const bool out_max = q[i] >= p.position_max_rad[i] && dq[i] > 0;
        const bool out_min = q[i] <= p.position_min_rad[i] && dq[i] < 0;
        if ((out_max || out_min) && !j.col(i).isZero()) {
          j.col(i).setZero();
          froze = true;
        }
      }
      if (!froze) break;
    }
    const JointVector trial = arm.clamp_to_limits(q + dq);
    const Vector6d trial_e = pose_error(arm.flange_in_cell(trial), target);
    const double trial_c = cost(trial_e, w);
    if (trial_c < c) {
      q = trial;
      e = trial_e;
      damping = std::max(damping * 0.3, 1e-9);
      // Stalled: the step no longer improves measurably (at a limit or the closest point).
      if (c - trial_c <= 1e-12 * c) {
        c = trial_c;
        break;
      }
      c = trial_c;
    } else {
      damping *= 10;
      if (damping > 1e6) break;  // no step direction improves: local minimum
    }
  }

  result.q = q;
  result.iterations = it;
  result.position_residual_m = e.head<3>().norm();
  result.orientation_residual_rad = e.tail<3>().norm();
  if (result.position_residual_m <= options.position_tolerance_m &&
      result.orientation_residual_rad <= options.orientation_tolerance_rad) {
    result.status = IkStatus::kConverged;
    return result;
  }
  // Short of the pose: blame a limit when a joint sits on one and pushing it further (the
  // unclamped gradient direction) would reduce the error.
  const Vector6d we = weights.asDiagonal() * e;
  const JointVector gradient = (weights.asDiagonal() * arm.jacobian(q)).transpose() * we;
  const double at_limit_rad = 1e-9;
  for (int i = 0; i < kIiwaJoints; ++i) {
    const bool at_max = q[i] >= p.position_max_rad[i] - at_limit_rad && gradient[i] > 0;
    const bool at_min = q[i] <= p.position_min_rad[i] + at_limit_rad && gradient[i] < 0;
    if (at_max || at_min) {
      result.status = IkStatus::kJointLimit;
      result.limited_joint = i;
      return result;
    }
  }
  result.status = IkStatus::kUnreachable;
  return result;
}

}  // namespace

IkResult solve_inverse_kinematics(const IiwaArm& arm, const Eigen::Isometry3d& target,
                                  const JointVector& seed, const IkOptions& options) {
  IkResult best = descend(arm, target, seed, options);
  if (best.status == IkStatus::kConverged || options.restarts <= 0) return best;
  const IiwaParameters& p = arm.parameters();
  std::mt19937 rng(options.restart_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int attempt = 1; attempt <= options.restarts; ++attempt) {
    JointVector restart;
    for (int i = 0; i < kIiwaJoints; ++i) {
      restart[i] = p.position_min_rad[i] +
                   unit(rng) * (p.position_max_rad[i] - p.position_min_rad[i]);
    }
    IkResult r = descend(arm, target, restart, options);
    r.attempts = attempt + 1;
    const bool better = r.status == IkStatus::kConverged ||
                        r.position_residual_m < best.position_residual_m;
    if (better) best = r;
    best.attempts = attempt + 1;
    if (best.status == IkStatus::kConverged) break;
  }
  return best;
}

}  // namespace drivers
