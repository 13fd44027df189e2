#pragma once
// Synthetic laser scans of a marked sheet, following the scan model of
// tracking/marker_extraction.h: hemispherical domes of radius r on the sheet, points uniform
// over each dome's area where the dome faces the scanner, isotropic Gaussian noise, stray points
// in the volume. Seeded, so every test sees the same scan.

#include <random>
#include <vector>

#include "tracking/types.h"

namespace tracking::testing {

struct SheetMarker {
  Vec3 base_m;  // centre of the dome's base, on the sheet surface
  Vec3 normal;  // unit sheet normal on the marker side
};

struct ScanSettings {
  double radius_m = 3.175e-3;
  double noise_m = 0.15e-3;       // standard deviation per coordinate
  int points_per_dome = 300;      // over the whole dome; the hidden part's share is dropped
  Vec3 viewpoint_m = Vec3::Zero();
};

// The points of one dome (noise included), in no particular order.
std::vector<Vec3> scan_dome(const SheetMarker& marker, const ScanSettings& settings,
                            std::mt19937& rng);

// Every marker's dome, concatenated.
std::vector<Vec3> scan_domes(const std::vector<SheetMarker>& markers, const ScanSettings& settings,
                             std::mt19937& rng);

// `count` points uniform in the box [low, high].
std::vector<Vec3> stray_points(int count, const Vec3& low, const Vec3& high, std::mt19937& rng);

// A 17 x 17 grid (row-major, spacing du x dv) on a sheet wrapped around a vertical cylinder of
// radius `radius_m` (axis along z through the origin): material u runs around the cylinder,
// v up it; u = 0 at the +x side, the grid centred there. Normals point outward.
std::vector<SheetMarker> cylinder_grid(double radius_m, double du_m, double dv_m, double z0_m);

// A 17 x 17 grid on a plane through `origin_m` spanned by the unit vectors `u_axis`, `v_axis`
// (normal u x v), grid centred on the origin.
std::vector<SheetMarker> plane_grid(const Vec3& origin_m, const Vec3& u_axis, const Vec3& v_axis,
                                    double du_m, double dv_m);

}  // namespace tracking::testing
