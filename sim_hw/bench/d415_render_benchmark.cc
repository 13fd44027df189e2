// Times the simulated D415: one depth render (z-buffer only) and one full frame (left + right IR
// renders, error model, colour render and shading) of a 6k-triangle hanging sheet plus floor, at
// 848x480 and 1280x720. Prints the median over 40 frames (ms). Not a test.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "sim_hw/d415_model.h"
#include "sim_hw/depth_renderer.h"
#include "sim_hw/simulated_d415.h"

namespace {

// A 1 m x 1 m sheet hanging in the x-z plane at y = 0, rippled along x, 55x55 cells (6050 tris).
std::shared_ptr<sim_hw::RenderScene> sheet_scene() {
  auto scene = std::make_shared<sim_hw::RenderScene>();
  auto sheet = sim_hw::make_grid_mesh("sheet", {0.0, 0.0, 1.0}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(),
                                      1.0, 1.0, 55, 55, {40, 40, 45});
  for (auto& v : sheet.vertices) v.y() += 0.05 * std::sin(6.0 * v.x()) * (1.5 - v.z());
  scene->meshes.push_back(std::move(sheet));
  scene->floor = sim_hw::FloorPlane{};
  return scene;
}

// Camera 1.5 m in front of the sheet (-y), 1.2 m up, looking along +y.
Eigen::Isometry3d camera_pose() {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d::UnitX();   // image right = cell x
  r.col(1) = -Eigen::Vector3d::UnitZ();  // image down = cell -z
  r.col(2) = Eigen::Vector3d::UnitY();   // optical axis = cell y
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  t.translation() = Eigen::Vector3d(0.0, -1.5, 1.2);
  return t;
}

template <class F>
double median_ms(F&& f) {
  std::vector<double> ms;
  for (int i = 0; i < 40; ++i) {
    const auto a = std::chrono::steady_clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count());
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

}  // namespace

int main() {
  const auto scene = sheet_scene();
  for (const drivers::StreamMode mode : {drivers::StreamMode{848, 480, 30}, drivers::StreamMode{1280, 720, 30}}) {
    sim_hw::RenderedView view;
    const auto k = sim_hw::d415_depth_intrinsics(mode);
    const double render = median_ms([&] { sim_hw::render_view(*scene, camera_pose(), k, view); });
    sim_hw::SimulatedD415Options options;
    options.scene = [scene](double) { return scene; };
    sim_hw::SimulatedD415Camera camera(options);
    drivers::CameraConfig config;
    config.name = "bench";
    config.depth_mode = config.color_mode = mode;
    config.camera_to_cell = camera_pose();
    if (!camera.configure(config).ok || !camera.activate().ok) return 1;
    drivers::DepthFrame frame;
    const double full = median_ms([&] { camera.read(frame); });
    fmt::print("d415 sim {}x{}: {} triangles + floor: depth render median {:.2f} ms, full frame median {:.2f} ms\n",
               mode.width, mode.height, scene->meshes[0].triangles.size(), render, full);
  }
  return 0;
}
