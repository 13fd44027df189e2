#include "sim_hw/openni2_sim_config.h"

#include <set>

#include "twin/base/json_field.h"

namespace sim_hw {
namespace {

drivers::StreamMode read_mode(const twin::JsonField& f) {
  f.only_keys({"width", "height", "fps"});
  return {f["width"].positive_integer(), f["height"].positive_integer(), f["fps"].positive_integer()};
}

drivers::Intrinsics read_intrinsics(const twin::JsonField& f) {
  f.only_keys({"width", "height", "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"});
  drivers::Intrinsics k;
  k.width = f["width"].positive_integer();
  k.height = f["height"].positive_integer();
  k.fx = f["fx"].positive("px");
  k.fy = f["fy"].positive("px");
  k.cx = f["cx"].number("px");
  k.cy = f["cy"].number("px");
  for (auto [key, value] :
       {std::pair{"k1", &k.k1}, {"k2", &k.k2}, {"p1", &k.p1}, {"p2", &k.p2}, {"k3", &k.k3}}) {
    if (auto d = f.optional(key)) *value = d->number("1");
  }
  return k;
}

Eigen::Isometry3d read_pose(const twin::JsonField& f) {
  if (!f.is_array() || f.array_size() != 16) f.fail("must be 16 numbers (row-major 4x4 transform, m)");
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = f[static_cast<std::size_t>(i)].number("m");
  Eigen::Isometry3d pose;
  pose.matrix() = m;
  const Eigen::Matrix3d r = pose.linear();
  if (!(r * r.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-6) ||
      m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
    f.fail("must be a rigid transform (orthonormal rotation, last row 0 0 0 1)");
  }
  return pose;
}

OpenNI2SimDeviceConfig read_device(const twin::JsonField& f) {
  f.only_keys({"name", "backend", "uri", "serial", "depth_mode", "color_mode", "depth_intrinsics",
               "color_intrinsics", "depth_to_color", "camera_to_cell", "read_timeout_ms", "on_demand",
               "replug_after_ms"});
  OpenNI2SimDeviceConfig d;
  drivers::CameraConfig& c = d.source;
  c.name = f["name"].string();
  if (c.name.empty()) f.fail_child("name", "must not be empty");
  c.backend = f["backend"].string();
  if (auto v = f.optional("uri")) c.uri = v->string();
  if (auto v = f.optional("serial")) c.serial = v->string();
  c.depth_mode = read_mode(f["depth_mode"]);
  c.color_mode = {0, 0, 0};
  if (auto v = f.optional("color_mode")) {
    c.color_mode = read_mode(*v);
    d.has_color = true;
  }
  if (auto v = f.optional("depth_intrinsics")) c.depth_intrinsics = read_intrinsics(*v);
  if (auto v = f.optional("color_intrinsics")) c.color_intrinsics = read_intrinsics(*v);
  if (auto v = f.optional("depth_to_color")) c.depth_to_color = read_pose(*v);
  if (auto v = f.optional("camera_to_cell")) c.camera_to_cell = read_pose(*v);
  if (auto v = f.optional("read_timeout_ms"))
    c.read_timeout = std::chrono::milliseconds(v->positive_integer());
  if (auto v = f.optional("on_demand")) {
    if (!v->json().is_boolean()) v->fail("must be true or false");
    d.on_demand = v->json().get<bool>();
  }
  if (auto v = f.optional("replug_after_ms")) {
    const double ms = v->number("ms");
    if (ms != static_cast<int>(ms) || ms < -1) v->fail("must be -1 (never) or a whole number of ms >= 0");
    d.replug_after_ms = static_cast<int>(ms);
  }
  return d;
}

}  // namespace

std::vector<OpenNI2SimDeviceConfig> read_openni2_sim_config(const std::string& path) {
  const nlohmann::json root = twin::JsonField::parse_file(path);
  const twin::JsonField list(root, path);
  if (!list.is_array()) list.fail("must be a list of camera entries");
  std::vector<OpenNI2SimDeviceConfig> devices;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.array_size(); ++i) {
    devices.push_back(read_device(list[i]));
    if (!names.insert(devices.back().source.name).second)
      list[i]["name"].fail("repeats an earlier camera name");
  }
  return devices;
}

}  // namespace sim_hw
