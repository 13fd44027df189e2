#include "twin/mesh/mesh_io.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace twin {
namespace {

std::string four_digits(double value) {
  std::ostringstream out;
  out << std::setprecision(4) << value;
  return out.str();
}

// Orthonormal in-plane axes for unit normal n: u = world x projected into the plane (world y
// when the plane is normal to x), v = n x u.
std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
  Vec3 u = Vec3::UnitX() - n.x() * n;
  if (u.norm() < 1e-6) u = Vec3::UnitY() - n.y() * n;
  u.normalize();
  return {u, n.cross(u)};
}

std::vector<Vec2> project_onto_best_fit_plane(const std::vector<Vec3>& p, double tolerance) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].allFinite()) {
      throw std::invalid_argument("sheet_mesh_from_flat: vertex " + std::to_string(i) +
                                  " is not finite");
    }
  }
  std::vector<Vec2> uv(p.size());
  const bool horizontal =
      std::all_of(p.begin(), p.end(), [&](const Vec3& q) { return q.z() == p[0].z(); });
  if (horizontal) {  // exact: no rounding from a fitted normal
    for (std::size_t i = 0; i < p.size(); ++i) uv[i] = p[i].head<2>();
    return uv;
  }
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& q : p) centroid += q;
  centroid /= static_cast<double>(p.size());
  Mat3 covariance = Mat3::Zero();
  for (const Vec3& q : p) covariance += (q - centroid) * (q - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(covariance);
  Vec3 n = eigen.eigenvectors().col(0);  // eigenvalues ascend: col 0 is the normal
  // Sign the normal towards +z (vertical planes: +y, then +x) so v = n x u is predictable.
  const double sign = std::abs(n.z()) > 1e-9 ? n.z() : std::abs(n.y()) > 1e-9 ? n.y() : n.x();
  if (sign < 0) n = -n;
  std::size_t worst = 0;
  double worst_distance = -1.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = std::abs((p[i] - centroid).dot(n));
    if (d > worst_distance) {
      worst_distance = d;
      worst = i;
    }
  }
  if (worst_distance > tolerance) {
    throw std::invalid_argument("sheet_mesh_from_flat: mesh is not flat: vertex " +
                                std::to_string(worst) + " is " + four_digits(worst_distance) +
                                " m from the best-fit plane (tolerance " + four_digits(tolerance) +
                                " m)");
  }
  const auto [u, v] = plane_axes(n);
  for (std::size_t i = 0; i < p.size(); ++i) uv[i] = Vec2(p[i].dot(u), p[i].dot(v));
  return uv;
}

// Flips all triangles if all are clockwise; mixed orientation is an error.
void orient_counter_clockwise(SheetMesh& sheet) {
  int ccw = 0, cw = 0, first_ccw = -1, first_cw = -1;
  const int n = sheet.vertex_count();
  for (int t = 0; t < sheet.triangle_count(); ++t) {
    const auto& tri = sheet.triangles[t];
    if (std::any_of(tri.begin(), tri.end(), [n](int i) { return i < 0 || i >= n; })) continue;
    const double area = sheet.rest_area(t);
    if (area > 0 && ccw++ == 0) first_ccw = t;
    if (area < 0 && cw++ == 0) first_cw = t;
  }
  if (cw == 0) return;
  if (ccw == 0) {
    for (auto& tri : sheet.triangles) std::swap(tri[1], tri[2]);
    return;
  }
  const bool mostly_ccw = ccw >= cw;
  throw std::invalid_argument(
      "sheet_mesh_from_flat: triangles have mixed orientation in (u, v): triangle " +
      std::to_string(mostly_ccw ? first_cw : first_ccw) + " is " +
      (mostly_ccw ? "clockwise" : "counter-clockwise") + " but " +
      std::to_string(std::max(ccw, cw)) + " of " + std::to_string(sheet.triangle_count()) +
      " are not");
}

}  // namespace

SheetMesh sheet_mesh_from_flat(const SurfaceMesh& mesh, double flatness_tolerance_m) {
  if (!(flatness_tolerance_m >= 0.0)) {
    throw std::invalid_argument("sheet_mesh_from_flat: flatness_tolerance_m must be >= 0");
  }
  if (mesh.positions.empty() || mesh.triangles.empty()) {
    throw std::invalid_argument("sheet_mesh_from_flat: mesh has no vertices or no triangles");
  }
  if (!mesh.uv.empty() && mesh.uv.size() != mesh.positions.size()) {
    throw std::invalid_argument("sheet_mesh_from_flat: uv has " + std::to_string(mesh.uv.size()) +
                                " entries for " + std::to_string(mesh.positions.size()) +
                                " vertices");
  }
  SheetMesh sheet;
  sheet.triangles = mesh.triangles;
  sheet.rest_uv =
      mesh.uv.empty() ? project_onto_best_fit_plane(mesh.positions, flatness_tolerance_m) : mesh.uv;
  orient_counter_clockwise(sheet);
  validate_sheet_mesh(sheet);
  if (!mesh.uv.empty()) {
    // Material coordinates are metres. Exporters usually write texture coordinates in [0, 1],
    // which would silently pre-stress the sheet: the uv area must be the surface area, within
    // 10 % so that a deformed result of the twin (which carries u v) still reads back.
    double surface = 0.0;
    for (const auto& t : mesh.triangles) {
      surface += 0.5 * (mesh.positions[t[1]] - mesh.positions[t[0]])
                           .cross(mesh.positions[t[2]] - mesh.positions[t[0]]).norm();
    }
    const double material = sheet.total_rest_area();
    if (std::abs(material - surface) > 0.1 * surface) {
      throw std::invalid_argument(
          "sheet_mesh_from_flat: the texture coordinates span " + four_digits(material) +
          " m^2 but the surface " + four_digits(surface) +
          " m^2; material coordinates (u v / vt) must be in metres on the undeformed sheet");
    }
  }
  return sheet;
}

SurfaceMesh surface_from_positions(const SheetMesh& sheet, const VecX& x) {
  const int n = sheet.vertex_count();
  if (x.size() != 3 * static_cast<Eigen::Index>(n)) {
    throw std::invalid_argument("surface_from_positions: x has " + std::to_string(x.size()) +
                                " entries, expected 3 x " + std::to_string(n));
  }
  SurfaceMesh mesh;
  mesh.positions.resize(n);
  for (int i = 0; i < n; ++i) mesh.positions[i] = vertex(x, i);
  mesh.triangles = sheet.triangles;
  mesh.uv = sheet.rest_uv;
  return mesh;
}

SheetMesh read_flat_sheet_mesh(const std::filesystem::path& path) {
  const SurfaceMesh mesh = read_surface_mesh(path);  // its errors name the file already
  try {
    return sheet_mesh_from_flat(mesh);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path.string() + ": " + e.what());
  }
}

}  // namespace twin
