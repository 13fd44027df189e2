#pragma once
// Random vectors drawn in a fixed order. In `Vec3(d(rng), d(rng), d(rng))` the order in which the
// three draws happen is unspecified: GCC makes z first, clang x first, so a lab built with one
// compiler made other trial sets than the same seed built with the other. These draw z, y, x,
// GCC's order, so the lab's sets from a GCC build stay what they were.
#include <random>

#include "twin/base/types.h"

namespace sim_hw {

template <class Distribution>
twin::Vec3 draw_vec3(Distribution& d, std::mt19937_64& rng) {
  const double z = d(rng);
  const double y = d(rng);
  const double x = d(rng);
  return {x, y, z};
}

}  // namespace sim_hw
