#include "sim_hw/marker_scan.h"

#include <cmath>

#include "sim_hw/ordered_draws.h"

namespace sim_hw {

void append_marker_scan(const twin::Vec3& base_m, const twin::Vec3& normal, int points,
                        double noise_m, std::mt19937_64& rng, std::vector<twin::Vec3>& scan) {
  const twin::Vec3 n = normal.normalized();
  // Two tangents completing n to an orthonormal frame.
  const twin::Vec3 a = std::abs(n.x()) < 0.9 ? twin::Vec3::UnitX() : twin::Vec3::UnitY();
  const twin::Vec3 t1 = n.cross(a).normalized(), t2 = n.cross(t1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_m);
  for (int i = 0; i < points; ++i) {
    // Uniform on the hemisphere: the height along n is uniform on [0, r] (Archimedes).
    const double h = unit(rng), phi = 2.0 * M_PI * unit(rng);
    const double s = std::sqrt(std::max(0.0, 1.0 - h * h));
    const twin::Vec3 p = base_m + kMarkerDomeRadius_m * (h * n + s * (std::cos(phi) * t1 + std::sin(phi) * t2));
    scan.push_back(p + draw_vec3(noise, rng));
  }
}

}  // namespace sim_hw
