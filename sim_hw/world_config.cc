#include "sim_hw/world_config.h"

#include <filesystem>
#include <set>
#include <stdexcept>

#include "drivers/camera_config_json.h"
#include "drivers/pose_json.h"
#include "sim_hw/d415_scene_file.h"
#include "twin/base/json_field.h"

namespace sim_hw {
namespace {

using twin::JsonField;
namespace fs = std::filesystem;

double optional_positive(const JsonField& parent, const char* key, double fallback, const char* unit) {
  const auto f = parent.optional(key);
  return f ? f->positive(unit) : fallback;
}

void read_physics(const JsonField& w, WorldConfig& c) {
  if (auto p = w.optional("physics")) {
    p->only_keys({"dt_s", "truth_hz", "truth_model", "grid_spacing_m"});
    c.dt_s = optional_positive(*p, "dt_s", c.dt_s, "s");
    c.truth_hz = optional_positive(*p, "truth_hz", c.truth_hz, "Hz");
    if (auto m = p->optional("truth_model")) {
      try {
        c.truth.model = parse_truth_model(m->string(), "truth_model");
      } catch (const std::invalid_argument&) {
        m->fail("must be \"independent\" (the plate model sharing nothing with the twin) or \"twin\"");
      }
      // The reference shell solves settled states, minutes each: not a real-time world's sheet.
      if (c.truth.model == TruthModel::kSplineShell) {
        m->fail("must be \"independent\" or \"twin\" (the spline shell is the scanner lab's reference, not a real-time "
                "sheet)");
      }
    }
    c.truth.grid_spacing_m = optional_positive(*p, "grid_spacing_m", c.truth.grid_spacing_m, "m");
    if (c.dt_s > 0.1) (*p)["dt_s"].fail("must be at most 0.1 s (the world runs in real time)");
  }
  if (auto a = w.optional("arms")) {
    a->only_keys({"status_hz"});
    c.arm_status_hz = optional_positive(*a, "status_hz", c.arm_status_hz, "Hz");
  }
  if (auto g = w.optional("grippers")) {
    g->only_keys({"status_hz", "capture_distance_m", "grip_radius_m", "open_width_m"});
    c.gripper_status_hz = optional_positive(*g, "status_hz", c.gripper_status_hz, "Hz");
    c.capture_distance_m = optional_positive(*g, "capture_distance_m", c.capture_distance_m, "m");
    c.open_width_m = optional_positive(*g, "open_width_m", c.open_width_m, "m");
    if (auto r = g->optional("grip_radius_m")) c.grip_radius_m = r->non_negative("m");
  }
}

void read_scene(const JsonField& w, WorldConfig& c) {
  const auto s = w.optional("scene");
  if (!s) return;
  s->only_keys({"floor_height_m", "boxes"});
  if (auto f = s->optional("floor_height_m")) c.static_scene.floor = FloorPlane{f->number("m"), {170, 170, 165}};
  if (auto boxes = s->optional("boxes")) {
    for (std::size_t i = 0; i < boxes->array_size(); ++i) {
      const JsonField b = (*boxes)[i];
      b.only_keys({"name", "min_m", "max_m"});
      const twin::Vec3 lo = b["min_m"].vec3("m"), hi = b["max_m"].vec3("m");
      if ((hi - lo).minCoeff() <= 0) b.fail("needs max_m > min_m on every axis");
      c.static_scene.meshes.push_back(make_box_mesh(b["name"].string(), lo, hi, {150, 140, 120}));
    }
  }
}

// The devices of a cell-config v4l2 uri "depth=PATH,color=PATH".
std::string uri_device(const std::string& uri, const std::string& key) {
  const std::string tag = key + "=";
  const auto at = uri.find(tag);
  if (at == std::string::npos) return "";
  const auto end = uri.find(',', at);
  return uri.substr(at + tag.size(), end == std::string::npos ? std::string::npos : end - at - tag.size());
}

void read_cameras(const JsonField& w, const std::string& world_path,
                  const std::vector<drivers::CameraConfig>& cell_cameras, WorldConfig& c) {
  const JsonField cams = w["cameras"];
  std::set<std::string> seen;
  for (std::size_t i = 0; i < cams.array_size(); ++i) {
    const JsonField f = cams[i];
    f.only_keys({"name", "camera_to_cell", "noise", "seed", "node_prefix", "depth_device", "color_device"});
    WorldCamera cam;
    const std::string name = f["name"].string();
    const drivers::CameraConfig* cell = nullptr;
    for (const auto& cc : cell_cameras)
      if (cc.name == name) cell = &cc;
    if (!cell) f["name"].fail("names no camera of the cell config (\"" + name + "\")");
    if (!seen.insert(name).second) f["name"].fail("repeats camera \"" + name + "\"");
    cam.config = *cell;
    cam.config.backend = "simulated";
    cam.config.uri.clear();  // the scene comes from the world, not from a scene file
    const std::string pose_path = f.path() + ".camera_to_cell";
    cam.config.camera_to_cell =
        drivers::parse_pose(drivers::JsonField(f["camera_to_cell"].json(), world_path, pose_path));
    if (auto n = f.optional("noise")) cam.noise = read_d415_noise(*n);
    if (auto s = f.optional("seed")) cam.seed = static_cast<std::uint64_t>(s->positive_integer());
    cam.node_prefix = f["node_prefix"].string();
    cam.depth_device = f["depth_device"].string();
    cam.color_device = f["color_device"].string();
    if (uri_device(cell->uri, "depth") != cam.depth_device)
      f["depth_device"].fail("must be the depth device of the cell config's uri \"" + cell->uri + "\"");
    if (uri_device(cell->uri, "color") != cam.color_device)
      f["color_device"].fail("must be the color device of the cell config's uri \"" + cell->uri + "\"");
    c.cameras.push_back(std::move(cam));
  }
  for (const auto& cc : cell_cameras)
    if (!seen.count(cc.name)) cams.fail("has no entry for the cell config's camera \"" + cc.name + "\"");
}

void read_plan(const std::string& cell_config_path, WorldConfig& c) {
  const nlohmann::json cell = JsonField::parse_file(cell_config_path);
  const JsonField plan_file = JsonField(cell, cell_config_path)["job"]["plan_file"];
  c.plan_path = (fs::path(cell_config_path).parent_path() / plan_file.string()).string();
  c.plan = plan_file.read_named_file([&] { return twin::read_grasp_plan(c.plan_path); });
  for (const twin::Grasp& g : c.plan.grasps)
    if (!c.hardware.find_gripper(g.gripper))
      throw std::invalid_argument(c.plan_path + ": grasp of gripper \"" + g.gripper +
                                  "\" which the cell config " + cell_config_path + " does not list");
}

}  // namespace

WorldConfig read_world_config(const std::string& cell_config_path, const std::string& world_path) {
  WorldConfig c;
  c.hardware = drivers::read_cell_hardware(cell_config_path);
  const std::vector<drivers::CameraConfig> cell_cameras = drivers::read_camera_configs(cell_config_path);
  read_plan(cell_config_path, c);

  const nlohmann::json document = JsonField::parse_file(world_path);
  const JsonField w(document, world_path);
  w.only_keys({"sheet", "material_file", "physics", "arms", "grippers", "scene", "cameras"});
  const std::string dir = fs::path(world_path).parent_path().string();
  c.sheet = twin::read_sheet_spec(w["sheet"], dir);
  const std::string material_path = (fs::path(dir) / w["material_file"].string()).string();
  c.material = twin::read_material_file(material_path);
  read_physics(w, c);
  read_scene(w, c);
  read_cameras(w, world_path, cell_cameras, c);
  return c;
}

}  // namespace sim_hw
