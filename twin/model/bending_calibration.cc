#include "twin/model/bending_calibration.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "twin/model/dihedral_angle.h"

namespace twin {
namespace {

Vec12 hinge_positions(const VecX& x, const Hinge& h) {
  Vec12 xh;
  for (int k = 0; k < 4; ++k) xh.segment<3>(3 * k) = x.segment<3>(3 * h.v[k]);
  return xh;
}

double mesh_extent(const SheetMesh& mesh) {
  Vec2 lo = mesh.rest_uv.front(), hi = lo;
  for (const Vec2& p : mesh.rest_uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

// Hinge angle per unit curvature, t_e(d), for the cylinder at `angle_rad`.
std::vector<double> unit_curvature_angles(const SheetMesh& mesh, const std::vector<Hinge>& hinges,
                                          double angle_rad) {
  // Small enough that theta is linear in kappa to ~1e-6, large enough for atan2's precision.
  const double kappa = 1e-3 / mesh_extent(mesh);
  const VecX x = wrap_on_cylinder(mesh, angle_rad, kappa);
  std::vector<double> t(hinges.size());
  for (std::size_t e = 0; e < hinges.size(); ++e) {
    t[e] = dihedral_angle(hinge_positions(x, hinges[e]), nullptr, nullptr) / kappa;
  }
  return t;
}

}  // namespace

BendingCalibration::BendingCalibration(const SheetMesh& mesh, const std::vector<Hinge>& hinges) {
  if (hinges.empty()) throw std::invalid_argument("sheet mesh has no interior edges to bend");
  weight_.resize(hinges.size());
  normal_.resize(hinges.size());
  for (std::size_t e = 0; e < hinges.size(); ++e) {
    const Hinge& h = hinges[e];
    const Vec2 edge = mesh.rest_uv[h.v[1]] - mesh.rest_uv[h.v[0]];
    const double area = (mesh.rest_area(h.triangle_a) + mesh.rest_area(h.triangle_b)) / 3.0;
    weight_[e] = edge.squaredNorm() / area;
    normal_[e] = Vec2(edge.y(), -edge.x()).normalized();
    hinge_area_m2_ += area;
  }
  // response(d, c) = sum_e w_e n_c^2 t_e(d)^2 for cylinder direction d and coefficient c.
  Mat2 response = Mat2::Zero();
  double scalar_response = 0.0;
  for (int d = 0; d < 2; ++d) {
    const std::vector<double> t = unit_curvature_angles(mesh, hinges, d * M_PI / 2.0);
    for (std::size_t e = 0; e < hinges.size(); ++e) {
      scalar_response += weight_[e] * t[e] * t[e];
      for (int c = 0; c < 2; ++c) {
        response(d, c) += weight_[e] * normal_[e](c) * normal_[e](c) * t[e] * t[e];
      }
    }
  }
  // Meshes of a handful of triangles can leave the 2x2 fit degenerate; they still get a single
  // isotropic factor matching the mean of the u and v cylinders.
  isotropic_factor_ = hinge_area_m2_ / scalar_response;
  // Energy along d: a response(d,0) + b response(d,1) = D_d / 2 * hinge_area.
  to_coefficients_ = 0.5 * hinge_area_m2_ * response.inverse();
}

std::vector<double> BendingCalibration::hinge_stiffnesses(double du, double dv) const {
  Vec2 ab = to_coefficients_ * Vec2(du, dv);
  if (!(ab.minCoeff() > 0.0) && du == dv) ab = Vec2::Constant(isotropic_factor_ * du);
  if (!(ab.minCoeff() > 0.0)) {
    throw std::invalid_argument(
        "bending rigidity ratio warp/weft = " + std::to_string(dv / du) +
        " is beyond what hinge bending on this mesh represents with positive stiffness");
  }
  std::vector<double> k(weight_.size());
  for (std::size_t e = 0; e < k.size(); ++e) {
    const Vec2& n = normal_[e];
    k[e] = weight_[e] * (ab(0) * n.x() * n.x() + ab(1) * n.y() * n.y());
  }
  return k;
}

VecX wrap_on_cylinder(const SheetMesh& mesh, double angle_rad, double curvature_1_m) {
  const Vec2 d(std::cos(angle_rad), std::sin(angle_rad));
  const Vec2 perp(-d.y(), d.x());
  VecX x(3 * mesh.vertex_count());
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    const double s = mesh.rest_uv[i].dot(d);   // arc length along the curvature direction
    const double t = mesh.rest_uv[i].dot(perp);  // along the cylinder axis
    const double along = std::sin(curvature_1_m * s) / curvature_1_m;
    const double up = (1.0 - std::cos(curvature_1_m * s)) / curvature_1_m;
    const Vec2 in_plane = along * d + t * perp;
    x.segment<3>(3 * i) = Vec3(in_plane.x(), in_plane.y(), up);
  }
  return x;
}

double effective_cylinder_rigidity(const SheetMesh& mesh, const std::vector<Hinge>& hinges,
                                   const std::vector<double>& stiffnesses, double angle_rad) {
  const std::vector<double> t = unit_curvature_angles(mesh, hinges, angle_rad);
  double energy_per_kappa_sq = 0.0, area = 0.0;
  for (std::size_t e = 0; e < hinges.size(); ++e) {
    energy_per_kappa_sq += stiffnesses[e] * t[e] * t[e];
    area += (mesh.rest_area(hinges[e].triangle_a) + mesh.rest_area(hinges[e].triangle_b)) / 3.0;
  }
  return 2.0 * energy_per_kappa_sq / area;
}

}  // namespace twin
