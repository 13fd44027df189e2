#pragma once
// The largest distance (m) between corresponding vertices of two sheets' positions (3n each):
// how the solver tests compare a result with a reference.

#include <algorithm>

#include "twin/base/types.h"

namespace testing_support {

inline double largest_vertex_distance(const twin::VecX& a, const twin::VecX& b) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i + 2 < a.size(); i += 3) {
    largest = std::max(largest, (a.segment<3>(i) - b.segment<3>(i)).norm());
  }
  return largest;
}

}  // namespace testing_support
