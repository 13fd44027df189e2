#pragma once
// Raw laser-scan points around one raised marker, as the scanner lab makes them and as
// tracking/marker_extraction.h expects them: the marker is a dome of radius r sitting on the
// sheet on the side its normal points to; its position is the centre of the dome's base, on
// the sheet. Points are spread evenly over the dome's surface, each with Gaussian noise.

#include <random>
#include <vector>

#include "twin/base/types.h"

namespace sim_hw {

constexpr double kMarkerDomeRadius_m = 3.175e-3;  // quarter-inch markers

void append_marker_scan(const twin::Vec3& base_m, const twin::Vec3& normal, int points,
                        double noise_m, std::mt19937_64& rng, std::vector<twin::Vec3>& scan);

}  // namespace sim_hw
