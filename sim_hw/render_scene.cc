#include "sim_hw/render_scene.h"

namespace sim_hw {

SceneMesh make_box_mesh(std::string name, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                        const Albedo& albedo) {
  SceneMesh m;
  m.name = std::move(name);
  m.albedo = albedo;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                            (i & 4) ? hi.z() : lo.z());
  }
  // Two triangles per face; the renderer shades both sides, so winding only matters for tidiness.
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

SceneMesh make_grid_mesh(std::string name, const Eigen::Vector3d& centre, const Eigen::Vector3d& u,
                         const Eigen::Vector3d& v, double size_u_m, double size_v_m, int nx, int ny,
                         const Albedo& albedo) {
  SceneMesh m;
  m.name = std::move(name);
  m.albedo = albedo;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double a = (double(i) / nx - 0.5) * size_u_m;
      const double b = (double(j) / ny - 0.5) * size_v_m;
      m.vertices.push_back(centre + a * u + b * v);
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int p = j * (nx + 1) + i;
      m.triangles.push_back({p, p + 1, p + nx + 2});
      m.triangles.push_back({p, p + nx + 2, p + nx + 1});
    }
  }
  return m;
}

}  // namespace sim_hw
