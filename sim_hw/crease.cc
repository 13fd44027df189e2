#include "sim_hw/crease.h"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace sim_hw {

int apply_crease(twin::ShellModel& model, const Crease& crease) {
  if (model.plate_bending()) {
    // The crease is written as hinge rest angles; a plate-bending twin has no hinges to bend.
    throw std::invalid_argument("crease: the twin-model truth creases hinges; its material must use "
                                "\"bending_model\": \"hinge\"");
  }
  const twin::SheetMesh& mesh = model.mesh();
  const twin::Vec2 normal(-std::sin(crease.direction_rad), std::cos(crease.direction_rad));
  const auto centroid = [&](int t) {
    const auto& tri = mesh.triangles[t];
    return ((mesh.rest_uv[tri[0]] + mesh.rest_uv[tri[1]] + mesh.rest_uv[tri[2]]) / 3.0).eval();
  };
  const auto& hinges = model.bending().hinges();
  const auto& elements = model.bending().elements();
  // Keep whatever rest angles the material gave (a rest curvature) and add the crease on top.
  std::vector<double> angles(hinges.size());
  int changed = 0;
  for (std::size_t i = 0; i < hinges.size(); ++i) {
    angles[i] = elements[i].rest_angle_rad;
    const double side_a = normal.dot(centroid(hinges[i].triangle_a) - crease.point_m);
    const double side_b = normal.dot(centroid(hinges[i].triangle_b) - crease.point_m);
    if ((side_a < 0.0) == (side_b < 0.0)) continue;
    const twin::Vec2 edge = mesh.rest_uv[hinges[i].v[1]] - mesh.rest_uv[hinges[i].v[0]];
    const twin::Vec2 edge_normal = twin::Vec2(-edge.y(), edge.x()).normalized();
    angles[i] += crease.angle_rad * std::abs(edge_normal.dot(normal));
    ++changed;
  }
  model.bending().set_rest_angles(angles);
  return changed;
}

}  // namespace sim_hw
