#pragma once
// Plain Eigen types for the tracking library. tracking may not depend on twin/, so it names its
// own vector type rather than borrowing twin::Vec3 (both are Eigen::Vector3d, so values pass
// between them without conversion). Lengths are metres unless a name says otherwise.

#include <Eigen/Core>

namespace tracking {

using Vec3 = Eigen::Vector3d;

}  // namespace tracking
