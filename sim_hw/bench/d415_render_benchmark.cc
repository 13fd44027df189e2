// Times the simulated D415: one depth render (z-buffer only) and one full frame (left + right IR
// renders, error model, colour render and shading) of a 6k-triangle hanging sheet plus floor, at
// 848x480 and 1280x720. Prints the median over 40 frames (ms) of wall time and of this thread's
// CPU time (the latter is robust when other processes share the cores). Not a test.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "sim_hw/d415_model.h"
#include "sim_hw/depth_renderer.h"
#include "sim_hw/sheet_scene.h"
#include "sim_hw/simulated_d415.h"

namespace {

// The twin's 1 m x 1 m sheet (~6k triangles) hanging in the x-z plane from z = 1.5 m, rippled.
std::shared_ptr<sim_hw::RenderScene> sheet_scene() {
  auto scene = std::make_shared<sim_hw::RenderScene>();
  const twin::SheetMesh sheet = twin::make_rectangular_sheet(1.0, 1.0, twin::edge_length_for_triangle_count(1.0, 1.0, 6000));
  twin::VecX x(3 * sheet.vertex_count());
  for (int i = 0; i < sheet.vertex_count(); ++i) {
    const double u = sheet.rest_uv[i].x() - 0.5, v = sheet.rest_uv[i].y();
    x.segment<3>(3 * i) = Eigen::Vector3d(u, 0.05 * std::sin(6.0 * u) * v, 1.5 - v);
  }
  scene->meshes.push_back(sim_hw::sheet_scene_mesh(sheet, x));
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

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * t.tv_sec + 1e-6 * t.tv_nsec;
}

struct Timing {
  double wall_ms, cpu_ms;  // medians
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

template <class F>
Timing time_it(F&& f) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < 40; ++i) {
    const auto a = std::chrono::steady_clock::now();
    const double c = thread_cpu_ms();
    f();
    cpu.push_back(thread_cpu_ms() - c);
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count());
  }
  return {median(wall), median(cpu)};
}

}  // namespace

int main() {
  const auto scene = sheet_scene();
  for (const drivers::StreamMode mode : {drivers::StreamMode{848, 480, 30}, drivers::StreamMode{1280, 720, 30}}) {
    sim_hw::RenderedView view;
    const auto k = sim_hw::d415_depth_intrinsics(mode);
    const Timing render = time_it([&] { sim_hw::render_view(*scene, camera_pose(), k, view); });
    sim_hw::SimulatedD415Options options;
    options.scene = [scene](double) { return scene; };
    sim_hw::SimulatedD415Camera camera(options);
    drivers::CameraConfig config;
    config.name = "bench";
    config.depth_mode = config.color_mode = mode;
    config.camera_to_cell = camera_pose();
    if (!camera.configure(config).ok || !camera.activate().ok) return 1;
    drivers::DepthFrame frame;
    const Timing full = time_it([&] { camera.read(frame); });
    fmt::print(
        "d415 sim {}x{}, {} triangles + floor: depth render median {:.2f} ms (cpu {:.2f}), "
        "full frame (left+right+colour renders, error model) median {:.2f} ms (cpu {:.2f})\n",
        mode.width, mode.height, scene->meshes[0].triangles.size(), render.wall_ms, render.cpu_ms, full.wall_ms,
        full.cpu_ms);
  }
  return 0;
}
