#include "drivers/camera_config_json.h"
#include "drivers/pose_json.h"

#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

#include "drivers/json_field.h"

namespace drivers {
namespace {

using nlohmann::json;


StreamMode parse_mode(const JsonField& f) {
  f.only_keys({"width", "height", "fps"});
  return {f["width"].positive_int(), f["height"].positive_int(), f["fps"].positive_int()};
}

Intrinsics parse_intrinsics(const JsonField& f, const StreamMode& mode, const char* mode_name) {
  f.only_keys({"width", "height", "fx", "fy", "cx", "cy", "distortion"});
  Intrinsics k;
  k.width = f["width"].positive_int();
  k.height = f["height"].positive_int();
  if (k.width != mode.width || k.height != mode.height)
    f.fail("size " + std::to_string(k.width) + "x" + std::to_string(k.height) + " must equal " +
           mode_name + " " + std::to_string(mode.width) + "x" + std::to_string(mode.height));
  k.fx = f["fx"].positive();
  k.fy = f["fy"].positive();
  k.cx = f["cx"].number();
  k.cy = f["cy"].number();
  if (f.has("distortion")) {
    const std::vector<double> d = f["distortion"].numbers(5);
    k.k1 = d[0], k.k2 = d[1], k.p1 = d[2], k.p2 = d[3], k.k3 = d[4];
  }
  return k;
}


CameraConfig parse_camera(const json& value, const std::string& where) {
  const JsonField f(value, where, "");
  f.only_keys({"name", "backend", "uri", "serial", "depth_mode", "color_mode", "depth_intrinsics",
               "color_intrinsics", "depth_to_color", "camera_to_cell", "depth_unit_mm",
               "read_timeout_ms", "stale_after_ms", "frozen_after_frames"});
  CameraConfig c;
  c.name = f["name"].string();
  if (c.name.empty()) f["name"].fail("must not be empty");
  c.backend = f["backend"].string();
  c.uri = f["uri"].string();
  if (f.has("serial")) c.serial = f["serial"].string();
  if (f.has("depth_mode")) c.depth_mode = parse_mode(f["depth_mode"]);
  if (f.has("color_mode")) c.color_mode = parse_mode(f["color_mode"]);
  // Optional: a back-end that cannot read the calibration from the device (V4L2) refuses at
  // configure() without it; the simulated D415 and OpenNI2 supply their own.
  if (f.has("depth_intrinsics"))
    c.depth_intrinsics = parse_intrinsics(f["depth_intrinsics"], c.depth_mode, "depth_mode");
  if (f.has("color_intrinsics"))
    c.color_intrinsics = parse_intrinsics(f["color_intrinsics"], c.color_mode, "color_mode");
  if (f.has("depth_to_color")) c.depth_to_color = parse_pose(f["depth_to_color"]);
  c.camera_to_cell = parse_pose(f["camera_to_cell"]);
  if (f.has("depth_unit_mm")) c.depth_unit_mm = f["depth_unit_mm"].positive();
  if (f.has("read_timeout_ms"))
    c.read_timeout = std::chrono::milliseconds(f["read_timeout_ms"].positive_int());
  if (f.has("stale_after_ms"))
    c.stale_after = std::chrono::milliseconds(f["stale_after_ms"].positive_int());
  if (f.has("frozen_after_frames")) {
    c.frozen_after_frames = f["frozen_after_frames"].positive_int();
    if (c.frozen_after_frames < 2) f["frozen_after_frames"].fail("must be >= 2 (images in a row)");
  }
  return c;
}

}  // namespace

std::vector<CameraConfig> parse_camera_configs(const json& document, const std::string& source) {
  const json* cameras = &document;
  if (document.is_object()) {
    if (!document.contains("cameras")) throw std::invalid_argument(source + ": field 'cameras' is missing");
    cameras = &document.at("cameras");
  }
  if (!cameras->is_array() || cameras->empty())
    throw std::invalid_argument(source + ": field 'cameras' must be a non-empty array of camera objects");
  std::vector<CameraConfig> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < cameras->size(); ++i) {
    const json& cam = (*cameras)[i];
    std::string where = source + ": camera " + std::to_string(i);
    if (cam.is_object() && cam.contains("name") && cam["name"].is_string())
      where += " (" + cam["name"].get<std::string>() + ")";
    if (!cam.is_object()) throw std::invalid_argument(where + " must be an object");
    out.push_back(parse_camera(cam, where));
    if (!names.insert(out.back().name).second)
      throw std::invalid_argument(where + ": field 'name' repeats an earlier camera's name");
  }
  return out;
}

std::vector<CameraConfig> read_camera_configs(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open camera config file");
  const json document = parse_json_stream(in, path);
  return parse_camera_configs(document, path);
}

}  // namespace drivers
