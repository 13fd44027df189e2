#include "drivers/joint_command_limiter.h"

#include <algorithm>
#include <cmath>

namespace drivers {

LimitedCommand limit_joint_command(const IiwaParameters& parameters, const JointVector& current,
                                   const JointVector& target, double dt_s,
                                   double velocity_scale) {
  LimitedCommand out;
  if (!target.allFinite() || !current.allFinite() || !(dt_s > 0) || !(velocity_scale > 0)) {
    out.q = current;
    out.position_clamped = true;
    out.velocity_clamped = true;
    return out;
  }
  const JointVector clamped =
      target.cwiseMax(parameters.position_min_rad).cwiseMin(parameters.position_max_rad);
  out.position_clamped = (clamped.array() != target.array()).any();

  // One common factor keeps the step's direction.
  const JointVector step = clamped - current;
  const double scale = std::min(velocity_scale, 1.0);
  double factor = 1.0;
  for (int i = 0; i < kIiwaJoints; ++i) {
    const double max_step = parameters.velocity_max_rad_s[i] * scale * dt_s;
    if (std::abs(step[i]) > max_step) factor = std::min(factor, max_step / std::abs(step[i]));
  }
  out.velocity_clamped = factor < 1.0;
  out.q = current + factor * step;
  // `current` itself may lie outside the limits (e.g. a measured overshoot): never command out.
  out.q = out.q.cwiseMax(parameters.position_min_rad).cwiseMin(parameters.position_max_rad);
  return out;
}

}  // namespace drivers
