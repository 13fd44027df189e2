#include "twin/model/hinge_bending.h"

#include <map>
#include <stdexcept>
#include <string>

#include "twin/model/dihedral_angle.h"

namespace twin {

std::vector<Hinge> build_hinges(const SheetMesh& mesh) {
  // Directed edge (a -> b, counter-clockwise in its triangle) -> (triangle, opposite vertex).
  std::map<std::pair<int, int>, std::pair<int, int>> directed;
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> edge{tri[k], tri[(k + 1) % 3]};
      if (!directed.emplace(edge, std::make_pair(t, tri[(k + 2) % 3])).second) {
        throw std::invalid_argument(
            "sheet mesh edge (" + std::to_string(edge.first) + ", " +
            std::to_string(edge.second) + ") is used twice in the same direction (triangles " +
            std::to_string(directed[edge].first) + " and " + std::to_string(t) +
            "): the mesh is non-manifold or inconsistently oriented");
      }
    }
  }
  std::vector<Hinge> hinges;
  for (const auto& [edge, info] : directed) {
    if (edge.first > edge.second) continue;  // visit each undirected edge once
    auto twin_edge = directed.find({edge.second, edge.first});
    if (twin_edge == directed.end()) continue;  // boundary edge
    Hinge h;
    h.v = {edge.first, edge.second, info.second, twin_edge->second.second};
    h.triangle_a = info.first;
    h.triangle_b = twin_edge->second.first;
    hinges.push_back(h);
  }
  return hinges;
}

double hinge_bending_energy(const HingeElement& h, const Vec12& xh, Vec12* grad, Mat12* hess,
                            HessianMode mode) {
  Vec12 g;
  Mat12 hth;
  const bool exact = hess && mode == HessianMode::kExact;
  const double theta =
      dihedral_angle(xh, (grad || hess) ? &g : nullptr, exact ? &hth : nullptr);
  const double d = theta - h.rest_angle_rad;
  const double qd2 = h.quartic_per_rad2 * d * d;
  // With q = 0 these are the quadratic hinge's 2 k d and 2 k, bit for bit.
  const double dpsi = 2.0 * h.stiffness_Nm * d * (1.0 + 2.0 * qd2);
  if (grad) *grad = dpsi * g;
  if (hess) {
    *hess = (2.0 * h.stiffness_Nm * (1.0 + 6.0 * qd2)) * g * g.transpose();
    if (exact) *hess += dpsi * hth;
  }
  return h.stiffness_Nm * d * d * (1.0 + qd2);
}

}  // namespace twin
