#pragma once
// Small scenes and poses shared by the simulated-D415 tests.

#include <memory>

#include <Eigen/Geometry>

#include "drivers/depth_camera.h"
#include "sim_hw/render_scene.h"

namespace sim_hw_test {

// A camera at height_m above the cell origin looking straight down (optical axis = cell -z).
inline Eigen::Isometry3d looking_down(double height_m) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  t.translation() = Eigen::Vector3d(0.0, 0.0, height_m);
  return t;
}

inline std::shared_ptr<sim_hw::RenderScene> floor_only() {
  auto s = std::make_shared<sim_hw::RenderScene>();
  s->floor = sim_hw::FloorPlane{};
  return s;
}

inline drivers::CameraConfig config_848(const std::string& name, const Eigen::Isometry3d& pose) {
  drivers::CameraConfig c;
  c.name = name;
  c.backend = "simulated";
  c.camera_to_cell = pose;
  return c;
}

}  // namespace sim_hw_test
