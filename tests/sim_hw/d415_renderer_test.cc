// The z-buffer renderer against exact geometry at pixel centres: a tilted plane, the analytic
// floor, a tessellated sphere (exact against its own triangles by ray casting, and within the
// tessellation error of the true sphere), and near-plane clipping.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "sim_hw/d415_model.h"
#include "sim_hw/depth_renderer.h"
#include "tests/sim_hw/d415_test_scenes.h"

namespace {

using sim_hw::RenderedView;

Eigen::Vector3d pixel_ray(const drivers::Intrinsics& k, int c, int r) {
  return {(c - k.cx) / k.fx, (r - k.cy) / k.fy, 1.0};
}

// Moller-Trumbore style ray/triangle test, independent of the rasterizer: the ray parameter t
// along `dir` from the origin, or -1.
double ray_triangle(const Eigen::Vector3d& dir, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return -1;
  const Eigen::Vector3d s = -a;
  const double u = s.dot(p) / det;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = dir.dot(q) / det;
  if (u < 0 || v < 0 || u + v > 1) return -1;
  return e2.dot(q) / det;
}

sim_hw::SceneMesh uv_sphere(const Eigen::Vector3d& centre, double radius, int slices, int stacks) {
  sim_hw::SceneMesh m;
  for (int j = 0; j <= stacks; ++j) {
    const double th = M_PI * j / stacks;
    for (int i = 0; i < slices; ++i) {
      const double ph = 2 * M_PI * i / slices;
      m.vertices.push_back(centre + radius * Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                                             std::cos(th)));
    }
  }
  for (int j = 0; j < stacks; ++j) {
    for (int i = 0; i < slices; ++i) {
      const int a = j * slices + i, b = j * slices + (i + 1) % slices;
      m.triangles.push_back({a, b, a + slices});
      m.triangles.push_back({b, b + slices, a + slices});
    }
  }
  return m;
}

}  // namespace

TEST_CASE("render: a tilted plane is exact at every pixel centre", "[camera_sim]") {
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  // Plane through (0, 0, 1.5) with normal n, as a coarse grid much larger than the view.
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, -1.0).normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  sim_hw::RenderScene scene;
  scene.meshes.push_back(sim_hw::make_grid_mesh("plane", {0, 0, 1.5}, u, v, 6.0, 6.0, 7, 5, {40, 40, 45}));
  RenderedView view;
  sim_hw::render_view(scene, Eigen::Isometry3d::Identity(), k, view);
  double worst = 0;
  int hits = 0;
  for (int r = 0; r < k.height; ++r) {
    for (int c = 0; c < k.width; ++c) {
      const Eigen::Vector3d d = pixel_ray(k, c, r);
      const double z_exact = n.dot(Eigen::Vector3d(0, 0, 1.5)) / n.dot(d);
      const float z = view.depth_m[r * k.width + c];
      REQUIRE(z > 0.0f);  // the plane covers the whole view: no cracks between triangles
      worst = std::max(worst, std::abs(z - z_exact));
      ++hits;
      REQUIRE(view.surface[r * k.width + c] == 0);
    }
  }
  CHECK(worst < 1e-4);  // float storage of z: well below a millimetre
  // Normals face the camera.
  CHECK(view.normal_cam[1000].cast<double>().dot(n) == Approx(1.0).margin(1e-5));  // n.p < 0 already
}

TEST_CASE("render: the analytic floor matches ray/plane intersection from a tilted camera", "[camera_sim]") {
  const auto k = sim_hw::d415_depth_intrinsics({1280, 720, 30});
  Eigen::Isometry3d pose = sim_hw_test::looking_down(1.3);
  pose.linear() = pose.linear() * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  sim_hw::RenderScene scene = *sim_hw_test::floor_only();
  scene.floor->height_m = 0.1;
  RenderedView view;
  sim_hw::render_view(scene, pose, k, view);
  for (int r = 0; r < k.height; r += 7) {
    for (int c = 0; c < k.width; c += 5) {
      const Eigen::Vector3d d_cell = pose.linear() * pixel_ray(k, c, r);
      const double t = (0.1 - pose.translation().z()) / d_cell.z();  // z of the ray = t (d.z = 1)
      const float z = view.depth_m[r * k.width + c];
      if (t > 0) {
        REQUIRE(z == Approx(t).epsilon(1e-6));
        REQUIRE(view.surface[r * k.width + c] == sim_hw::kFloorSurface);
      } else {
        REQUIRE(z == 0.0f);
      }
    }
  }
}

TEST_CASE("render: a tessellated sphere is exact against its triangles and near the true sphere", "[camera_sim]") {
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  const Eigen::Vector3d centre(0.05, -0.03, 1.0);
  const double radius = 0.2;
  sim_hw::RenderScene scene;
  scene.meshes.push_back(uv_sphere(centre, radius, 96, 48));
  const auto& mesh = scene.meshes[0];
  RenderedView view;
  sim_hw::render_view(scene, Eigen::Isometry3d::Identity(), k, view);
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> col(0, k.width - 1), row(0, k.height - 1);
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    const int c = col(rng), r = row(rng);
    const Eigen::Vector3d d = pixel_ray(k, c, r);
    double t_min = -1;
    for (const auto& tri : mesh.triangles) {
      const double t = ray_triangle(d, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
      if (t > 0 && (t_min < 0 || t < t_min)) t_min = t;
    }
    const float z = view.depth_m[r * k.width + c];
    if (t_min < 0) {
      REQUIRE(z == 0.0f);
      continue;
    }
    ++checked;
    REQUIRE(z == Approx(t_min).margin(2e-6));
  }
  CHECK(checked > 30);
  // Every hit lies within the chord error of the true sphere (radius * (1 - cos(pi / 48)) < 0.5 mm).
  double worst = 0;
  for (int r = 0; r < k.height; ++r) {
    for (int c = 0; c < k.width; ++c) {
      const float z = view.depth_m[r * k.width + c];
      if (z == 0.0f) continue;
      worst = std::max(worst, std::abs((pixel_ray(k, c, r) * z - centre).norm() - radius));
    }
  }
  CHECK(worst < 0.5e-3);
}

TEST_CASE("render: triangles crossing behind the camera are clipped, not smeared", "[camera_sim]") {
  const auto k = sim_hw::d415_depth_intrinsics({848, 480, 30});
  // A floor-like quad under a camera looking horizontally: it extends behind the camera.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // camera z = cell y, camera y = cell -z
  pose.translation() = Eigen::Vector3d(0, 0, 1.0);
  sim_hw::RenderScene mesh_floor, analytic = *sim_hw_test::floor_only();
  mesh_floor.meshes.push_back(sim_hw::make_grid_mesh("quad", {0, 0, 0}, Eigen::Vector3d::UnitX(),
                                                     Eigen::Vector3d::UnitY(), 40.0, 40.0, 1, 1, {1, 1, 1}));
  RenderedView a, b;
  sim_hw::render_view(mesh_floor, pose, k, a);
  sim_hw::render_view(analytic, pose, k, b);
  int compared = 0;
  for (std::size_t i = 0; i < a.depth_m.size(); ++i) {
    if (b.depth_m[i] == 0.0f || b.depth_m[i] > 15.0f) {  // beyond the quad's far edge
      continue;
    }
    ++compared;
    REQUIRE(a.depth_m[i] == Approx(b.depth_m[i]).epsilon(1e-5));
  }
  CHECK(compared > 100000);
  // The upper half of the image looks above the horizon: nothing there.
  CHECK(a.depth_m[10 * k.width + 400] == 0.0f);
}
