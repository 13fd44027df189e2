#include "twin/model/bending_stiffening.h"

#include <cmath>

namespace twin {

double cylinder_angle_per_curvature(const HingeCurvatureMap& map, int e, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return map.rest_angle(e, {c * c, s * s, c * s});
}

std::vector<double> stiffening_lengths(const HingeCurvatureMap& map,
                                       const BendingCalibration& calibration) {
  // Stiffnesses of an isotropic plate, up to a common factor that cancels below.
  const std::vector<double> k = calibration.hinge_stiffnesses(1.0, 1.0);
  const std::vector<double>& across = map.across_lengths_m();
  // S_d = sum k t_d^4 / t_e^2 / sum k t_d^2: the quartic-to-quadratic ratio of a cylinder
  // along d for d_e = |t_e| (lambda = 1); lambda^2 is its mean over u and v.
  double lambda_sq = 0.0;
  for (double angle : {0.0, M_PI / 2.0}) {
    double quartic = 0.0, quadratic = 0.0;
    for (int e = 0; e < map.hinge_count(); ++e) {
      const double t = cylinder_angle_per_curvature(map, e, angle);
      quadratic += k[e] * t * t;
      quartic += k[e] * t * t * t * t / (across[e] * across[e]);
    }
    lambda_sq += 0.5 * quartic / quadratic;
  }
  const double lambda = std::sqrt(lambda_sq);
  std::vector<double> d(across.size());
  for (std::size_t e = 0; e < d.size(); ++e) d[e] = lambda * across[e];
  return d;
}

}  // namespace twin
