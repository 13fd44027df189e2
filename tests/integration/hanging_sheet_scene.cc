#include "tests/integration/hanging_sheet_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sim_hw/d415_model.h"
#include "twin/model/clamp.h"
#include "twin/model/shell_model.h"
#include "twin/solvers/static_solver.h"

namespace integration {
namespace {

constexpr double kWidth = 1.17, kHeight = 0.975;  // the paper's composite sheet (m)

twin::Material composite() {
  twin::Material m;
  m.name = "composite (end-to-end test)";
  m.surface_density_kg_m2 = 0.3;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 5000.0;
  m.shear_stiffness_N_m = 5000.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 1e-3;
  m.poisson_ratio = 0.3;
  return m;
}

// Equilibrium of the sheet held by four clamps 10 % closer to its centre than flat, at 1.0 m.
twin::VecX hang(const twin::SheetMesh& mesh, const twin::Material& material) {
  const twin::ShellModel model(mesh, material);
  const std::vector<twin::ClampSpec> specs = {{"A", twin::Vec2(0.10, 0.05), 0.02},
                                              {"B", twin::Vec2(kWidth - 0.05, 0.15), 0.02},
                                              {"C", twin::Vec2(kWidth - 0.20, kHeight - 0.05), 0.02},
                                              {"D", twin::Vec2(0.05, kHeight - 0.30), 0.02}};
  const twin::ClampSet clamps(model.mesh(), specs);
  twin::SheetPlacement placement;
  placement.origin_m = twin::Vec3(-kWidth / 2, -kHeight / 2, 1.0);
  const twin::Vec3 centre = placement.to_world(twin::Vec2(kWidth / 2, kHeight / 2));
  std::vector<twin::ClampPose> poses(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    poses[i].position_m = centre + 0.9 * (placement.to_world(specs[i].material_point_m) - centre);
  }
  twin::VecX x = twin::place_flat(model.mesh(), placement);
  twin::StaticSolver statics(model);
  const twin::SolveReport report = statics.solve(clamps, poses, x);
  if (!report.usable()) throw std::runtime_error("hanging sheet: static solve failed");
  return x;
}

}  // namespace

HangingSheet make_hanging_sheet(int triangles) {
  HangingSheet s;
  s.mesh = twin::make_rectangular_sheet(
      kWidth, kHeight, twin::edge_length_for_triangle_count(kWidth, kHeight, triangles));
  const twin::Material truth = composite();
  twin::Material predicted = truth;
  predicted.bending_rigidity_u_Nm = predicted.bending_rigidity_v_Nm = 4e-3;
  predicted.tensile_stiffness_u_N_m = predicted.tensile_stiffness_v_N_m = 2500.0;
  s.truth_m = hang(s.mesh, truth);
  s.prediction_m = hang(s.mesh, predicted);
  return s;
}

tracking::SurfaceMesh to_surface_mesh(const twin::SheetMesh& mesh, const twin::VecX& x) {
  tracking::SurfaceMesh out;
  for (int i = 0; i < mesh.vertex_count(); ++i) {
    out.vertices_m.push_back(twin::vertex(x, i));
    out.rest_uv_m.push_back(mesh.rest_uv[i]);
  }
  for (const auto& t : mesh.triangles) out.triangles.emplace_back(t[0], t[1], t[2]);
  return out;
}

Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear().col(0) = x;
  t.linear().col(1) = y;
  t.linear().col(2) = z;
  t.translation() = eye;
  return t;
}

std::vector<drivers::CameraConfig> three_cameras(const twin::VecX& sheet_m, int width, int height) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  const int n = static_cast<int>(sheet_m.size() / 3);
  for (int i = 0; i < n; ++i) centre += sheet_m.segment<3>(3 * i);
  centre /= n;
  // Front camera high and in front; the side cameras lower and wider, as in the paper's cell.
  const std::vector<std::pair<const char*, Eigen::Vector3d>> eyes = {
      {"cam_front", centre + Eigen::Vector3d(0.0, -1.0, 0.9)},
      {"cam_left", centre + Eigen::Vector3d(-1.1, 0.5, 0.8)},
      {"cam_right", centre + Eigen::Vector3d(1.0, 0.7, 1.0)}};
  std::vector<drivers::CameraConfig> configs;
  for (const auto& [name, eye] : eyes) {
    drivers::CameraConfig c;
    c.name = name;
    c.backend = "simulated";
    c.depth_mode = c.color_mode = {width, height, 30};
    c.depth_intrinsics = sim_hw::d415_depth_intrinsics(c.depth_mode);
    c.color_intrinsics = sim_hw::d415_color_intrinsics(c.color_mode);
    c.depth_to_color = sim_hw::d415_depth_to_color();
    c.camera_to_cell = look_at(eye, centre);
    configs.push_back(c);
  }
  return configs;
}

std::vector<double> distances_to_surface(const std::vector<Eigen::Vector3d>& points,
                                         const twin::SheetMesh& mesh, const twin::VecX& x) {
  struct Sphere {
    Eigen::Vector3d centre;
    double radius;
  };
  std::vector<Sphere> spheres;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d c = (twin::vertex(x, t[0]) + twin::vertex(x, t[1]) + twin::vertex(x, t[2])) / 3;
    double r = 0;
    for (int k = 0; k < 3; ++k) r = std::max(r, (twin::vertex(x, t[k]) - c).norm());
    spheres.push_back({c, r});
  }
  std::vector<double> out;
  for (const Eigen::Vector3d& p : points) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      if ((p - spheres[f].centre).norm() - spheres[f].radius >= best) continue;
      const auto& t = mesh.triangles[f];
      const Eigen::Vector3d q =
          tracking::closest_point_on_triangle(p, twin::vertex(x, t[0]), twin::vertex(x, t[1]), twin::vertex(x, t[2]));
      best = std::min(best, (p - q).norm());
    }
    out.push_back(best);
  }
  return out;
}

}  // namespace integration
