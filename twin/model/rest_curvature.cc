#include "twin/model/rest_curvature.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "twin/model/dihedral_angle.h"

namespace twin {

HingeCurvatureMap::HingeCurvatureMap(const SheetMesh& mesh, const std::vector<Hinge>& hinges) {
  coefficients_.resize(hinges.size());
  across_m_.resize(hinges.size());
  normals_.resize(hinges.size());
  for (std::size_t e = 0; e < hinges.size(); ++e) {
    const Hinge& h = hinges[e];
    Vec12 flat;
    for (int k = 0; k < 4; ++k) {
      const Vec2& uv = mesh.rest_uv[h.v[k]];
      flat.segment<3>(3 * k) = Vec3(uv.x(), uv.y(), 0.0);
    }
    Vec12 grad;
    const double theta = dihedral_angle(flat, &grad, nullptr);
    if (!std::isfinite(theta)) {
      throw std::invalid_argument("rest curvature: hinge " + std::to_string(e) + " (vertices " +
                                  std::to_string(h.v[0]) + ", " + std::to_string(h.v[1]) +
                                  ") has a degenerate rest triangle");
    }
    // Offsets from the hinge's edge midpoint keep the terms small (the result is the same for
    // any reference point, see the header).
    const Vec2 centre = 0.5 * (mesh.rest_uv[h.v[0]] + mesh.rest_uv[h.v[1]]);
    Vec3 a = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      const Vec2 d = mesh.rest_uv[h.v[k]] - centre;
      // w_k = 1/2 uu du^2 + 1/2 vv dv^2 + uv du dv
      a += grad(3 * k + 2) * Vec3(0.5 * d.x() * d.x(), 0.5 * d.y() * d.y(), d.x() * d.y());
    }
    coefficients_[e] = a;
    const Vec2 edge = mesh.rest_uv[h.v[1]] - mesh.rest_uv[h.v[0]];
    const Vec2 n = Vec2(edge.y(), -edge.x()).normalized();
    normals_[e] = n;
    across_m_[e] = std::abs(rest_angle(static_cast<int>(e), {n.x() * n.x(), n.y() * n.y(),
                                                             n.x() * n.y()}));
    if (!(across_m_[e] > 0.0)) {
      throw std::invalid_argument("rest curvature: hinge " + std::to_string(e) +
                                  " does not bend under curvature across it (degenerate)");
    }
  }
}

std::vector<double> HingeCurvatureMap::rest_angles(const CurvatureTensor& k) const {
  std::vector<double> angles(coefficients_.size());
  for (std::size_t e = 0; e < angles.size(); ++e) angles[e] = rest_angle(static_cast<int>(e), k);
  return angles;
}

}  // namespace twin
