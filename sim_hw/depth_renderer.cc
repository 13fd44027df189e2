#include "sim_hw/depth_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sim_hw {
namespace {

// Triangles are clipped against this plane in front of the camera so that vertices behind it
// never reach the projection (m).
constexpr double kNearM = 0.01;
constexpr float kFar = std::numeric_limits<float>::infinity();

struct Target {
  const drivers::Intrinsics& k;
  RenderedView& view;
};

// Fills the pixels whose centres lie inside the projected triangle (all z >= kNearM) where it is
// nearer than what the buffer holds.
void rasterize(const std::array<Eigen::Vector3d, 3>& p, const Eigen::Vector3f& normal,
               std::int32_t id, Target& t) {
  const auto& k = t.k;
  double u[3], v[3], w[3];
  for (int i = 0; i < 3; ++i) {
    w[i] = 1.0 / p[i].z();
    u[i] = k.fx * p[i].x() * w[i] + k.cx;
    v[i] = k.fy * p[i].y() * w[i] + k.cy;
  }
  const double area = (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]);
  if (std::abs(area) < 1e-12) return;  // edge-on: covers no pixel centre
  const int c0 = std::max(0, int(std::ceil(std::min({u[0], u[1], u[2]}))));
  const int c1 = std::min(k.width - 1, int(std::floor(std::max({u[0], u[1], u[2]}))));
  const int r0 = std::max(0, int(std::ceil(std::min({v[0], v[1], v[2]}))));
  const int r1 = std::min(k.height - 1, int(std::floor(std::max({v[0], v[1], v[2]}))));
  if (c0 > c1 || r0 > r1) return;
  // Barycentric l_i = A_i u + B_i v + C_i, from the edge opposite vertex i.
  double a[3], b[3], c[3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, m = (i + 2) % 3;
    a[i] = -(v[m] - v[j]) / area;
    b[i] = (u[m] - u[j]) / area;
    c[i] = ((v[m] - v[j]) * u[j] - (u[m] - u[j]) * v[j]) / area;
  }
  // Pixel centres exactly on a shared edge belong to both triangles (same depth), so no cracks.
  constexpr double kEps = -1e-9;
  for (int r = r0; r <= r1; ++r) {
    double l0 = a[0] * c0 + b[0] * r + c[0];
    double l1 = a[1] * c0 + b[1] * r + c[1];
    double l2 = a[2] * c0 + b[2] * r + c[2];
    const std::size_t row = std::size_t(r) * k.width;
    for (int col = c0; col <= c1; ++col, l0 += a[0], l1 += a[1], l2 += a[2]) {
      if (l0 < kEps || l1 < kEps || l2 < kEps) continue;
      const double z = 1.0 / (l0 * w[0] + l1 * w[1] + l2 * w[2]);
      const std::size_t idx = row + col;
      if (float(z) < t.view.depth_m[idx]) {
        t.view.depth_m[idx] = float(z);
        t.view.normal_cam[idx] = normal;
        t.view.surface[idx] = id;
      }
    }
  }
}

// Clips a triangle against z >= kNearM (Sutherland-Hodgman) and rasterizes the pieces.
void clip_and_rasterize(const std::array<Eigen::Vector3d, 3>& tri, std::int32_t id, Target& t) {
  Eigen::Vector3d n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
  const double len = n.norm();
  if (!(len > 0.0)) return;  // degenerate triangle
  n /= len;
  if (n.dot(tri[0]) > 0.0) n = -n;  // face the camera (both sides of a sheet are visible)
  const Eigen::Vector3f nf = n.cast<float>();
  if (tri[0].z() >= kNearM && tri[1].z() >= kNearM && tri[2].z() >= kNearM) {
    rasterize(tri, nf, id, t);
    return;
  }
  std::array<Eigen::Vector3d, 4> poly;
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& s = tri[i];
    const Eigen::Vector3d& e = tri[(i + 1) % 3];
    const bool s_in = s.z() >= kNearM, e_in = e.z() >= kNearM;
    if (s_in) poly[count++] = s;
    if (s_in != e_in) {
      const double f = (kNearM - s.z()) / (e.z() - s.z());
      poly[count++] = s + f * (e - s);
    }
  }
  for (int i = 1; i + 1 < count; ++i) rasterize({poly[0], poly[i], poly[i + 1]}, nf, id, t);
}

void render_floor(const FloorPlane& floor, const Eigen::Isometry3d& cell_to_camera,
                  const drivers::Intrinsics& k, RenderedView& view) {
  // Plane n.x = d in the camera frame; camera centre is the origin.
  Eigen::Vector3d n = cell_to_camera.linear() * Eigen::Vector3d::UnitZ();
  const double d = n.dot(cell_to_camera * Eigen::Vector3d(0.0, 0.0, floor.height_m));
  if (std::abs(d) < 1e-12) return;  // camera inside the plane: sees it edge-on
  const Eigen::Vector3f facing = (d > 0.0 ? -n : n).cast<float>();
  for (int r = 0; r < k.height; ++r) {
    const double y = (r - k.cy) / k.fy;
    for (int col = 0; col < k.width; ++col) {
      const double x = (col - k.cx) / k.fx;
      const double nd = n.x() * x + n.y() * y + n.z();  // ray (x, y, 1)
      if (nd * d <= 0.0) continue;                        // parallel or behind the camera
      const double z = d / nd;
      if (z < kNearM) continue;
      const std::size_t idx = std::size_t(r) * k.width + col;
      view.depth_m[idx] = float(z);
      view.normal_cam[idx] = facing;
      view.surface[idx] = kFloorSurface;
    }
  }
}

}  // namespace

void render_view(const RenderScene& scene, const Eigen::Isometry3d& camera_to_cell,
                 const drivers::Intrinsics& intrinsics, RenderedView& view) {
  const std::size_t n = std::size_t(intrinsics.width) * intrinsics.height;
  view.width = intrinsics.width;
  view.height = intrinsics.height;
  view.depth_m.assign(n, kFar);
  view.normal_cam.assign(n, Eigen::Vector3f::Zero());
  view.surface.assign(n, kNoSurface);
  const Eigen::Isometry3d cell_to_camera = camera_to_cell.inverse();
  if (scene.floor) render_floor(*scene.floor, cell_to_camera, intrinsics, view);
  Target target{intrinsics, view};
  std::vector<Eigen::Vector3d> cam;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& mesh = scene.meshes[m];
    cam.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < cam.size(); ++i) cam[i] = cell_to_camera * mesh.vertices[i];
    for (const auto& tri : mesh.triangles) {
      clip_and_rasterize({cam[tri[0]], cam[tri[1]], cam[tri[2]]}, std::int32_t(m), target);
    }
  }
  for (float& z : view.depth_m) {
    if (z == kFar) z = 0.0f;
  }
}

}  // namespace sim_hw
