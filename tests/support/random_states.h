#pragma once
// Seeded random deformed states for derivative tests: a rest shape placed in 3D by a random
// rotation, then stretched, sheared and bent by random perturbations of a given size.

#include <random>

#include <Eigen/Geometry>

#include "twin/base/types.h"

namespace twin::testing {

inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// Rest points (u, v) -> 3D (rotated, translated), each coordinate perturbed by up to
// `relative` times `scale` (uniform).
inline VecX random_deformed(const std::vector<Vec2>& rest, double scale, double relative,
                            std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Mat3 r = random_rotation(rng);
  const Vec3 t(u(rng), u(rng), u(rng));
  VecX x(3 * rest.size());
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const Vec3 p(rest[i].x(), rest[i].y(), 0.0);
    const Vec3 noise(u(rng), u(rng), u(rng));
    x.segment<3>(3 * i) = r * p + t + relative * scale * noise;
  }
  return x;
}

}  // namespace twin::testing
