#include "synthetic_scan.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace tracking::testing {

std::vector<Vec3> scan_dome(const SheetMarker& marker, const ScanSettings& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, s.noise_m);
  const Vec3 n = marker.normal.normalized();
  const Vec3 t1 = n.unitOrthogonal();
  const Vec3 t2 = n.cross(t1);
  std::vector<Vec3> points;
  for (int k = 0; k < s.points_per_dome; ++k) {
    // Archimedes: on a sphere the area between two heights is proportional to their gap, so a
    // uniform height and a uniform azimuth give points uniform over the dome's area.
    const double h = s.radius_m * unit(rng);
    const double phi = 2.0 * std::numbers::pi * unit(rng);
    const double rho = std::sqrt(std::max(0.0, s.radius_m * s.radius_m - h * h));
    const Vec3 p = marker.base_m + rho * (std::cos(phi) * t1 + std::sin(phi) * t2) + h * n;
    // Seen only where the dome's outward normal faces the scanner (a convex dome on a sheet the
    // scanner looks at from the marker side is then not hidden by anything else).
    const Vec3 outward = (p - marker.base_m) / s.radius_m;
    if (outward.dot(s.viewpoint_m - p) <= 0.0) continue;
    points.push_back(p + Vec3(noise(rng), noise(rng), noise(rng)));
  }
  return points;
}

std::vector<Vec3> scan_domes(const std::vector<SheetMarker>& markers, const ScanSettings& s,
                             std::mt19937& rng) {
  std::vector<Vec3> points;
  for (const SheetMarker& m : markers) {
    const std::vector<Vec3> dome = scan_dome(m, s, rng);
    points.insert(points.end(), dome.begin(), dome.end());
  }
  return points;
}

std::vector<Vec3> stray_points(int count, const Vec3& low, const Vec3& high, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> points;
  for (int k = 0; k < count; ++k) {
    const Vec3 a(unit(rng), unit(rng), unit(rng));
    points.push_back(low + a.cwiseProduct(high - low));
  }
  return points;
}

std::vector<SheetMarker> cylinder_grid(double radius_m, double du_m, double dv_m, double z0_m) {
  std::vector<SheetMarker> markers;
  for (int row = 0; row < 17; ++row) {
    for (int col = 0; col < 17; ++col) {
      const double angle = (col - 8) * du_m / radius_m;  // arc length u along the cylinder
      const Vec3 normal(std::cos(angle), std::sin(angle), 0.0);
      markers.push_back({radius_m * normal + Vec3(0.0, 0.0, z0_m + (row - 8) * dv_m), normal});
    }
  }
  return markers;
}

std::vector<SheetMarker> plane_grid(const Vec3& origin_m, const Vec3& u_axis, const Vec3& v_axis,
                                    double du_m, double dv_m) {
  const Vec3 normal = u_axis.cross(v_axis).normalized();
  std::vector<SheetMarker> markers;
  for (int row = 0; row < 17; ++row) {
    for (int col = 0; col < 17; ++col) {
      markers.push_back({origin_m + (col - 8) * du_m * u_axis + (row - 8) * dv_m * v_axis, normal});
    }
  }
  return markers;
}

}  // namespace tracking::testing
