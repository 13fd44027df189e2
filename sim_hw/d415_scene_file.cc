#include "sim_hw/d415_scene_file.h"

#include <filesystem>

#include "twin/base/json_field.h"
#include "twin/mesh/mesh_io.h"

namespace sim_hw {
namespace {

using twin::JsonField;

Albedo albedo(const JsonField& f) {
  const Eigen::Vector3d v = f.vec3("RGB counts 0..255");
  for (int i = 0; i < 3; ++i) {
    if (v[i] < 0.0 || v[i] > 255.0) f.fail("must hold RGB values in 0..255");
  }
  return v.cast<float>();
}

double get(const JsonField& parent, const char* key, double fallback, const char* unit) {
  const auto f = parent.optional(key);
  return f ? f->number(unit) : fallback;
}

bool get_bool(const JsonField& parent, const char* key, bool fallback) {
  const auto f = parent.optional(key);
  if (!f) return fallback;
  if (!f->json().is_boolean()) f->fail("must be true or false");
  return f->json().get<bool>();
}

SceneMesh inline_mesh(const JsonField& m) {
  SceneMesh mesh;
  const JsonField verts = m["vertices"];
  for (std::size_t i = 0; i < verts.array_size(); ++i) mesh.vertices.push_back(verts[i].vec3("m"));
  const JsonField tris = m["triangles"];
  for (std::size_t i = 0; i < tris.array_size(); ++i) {
    const JsonField t = tris[i];
    if (t.array_size() != 3) t.fail("must be [a, b, c] vertex indices");
    std::array<int, 3> tri{};
    for (std::size_t j = 0; j < 3; ++j) {
      const auto& v = t[j].json();
      if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() >= (long long)mesh.vertices.size()) {
        t[j].fail("must be a vertex index in 0.." + std::to_string(mesh.vertices.size() - 1));
      }
      tri[j] = int(v.get<long long>());
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

SceneMesh read_mesh(const JsonField& m, const std::filesystem::path& dir) {
  m.only_keys({"name", "file", "vertices", "triangles", "albedo"});
  SceneMesh mesh;
  if (m.has("file")) {
    if (m.has("vertices") || m.has("triangles")) m.fail("must have either 'file' or 'vertices'+'triangles'");
    std::filesystem::path file = m["file"].string();
    if (file.is_relative()) file = dir / file;
    const twin::SurfaceMesh s = m["file"].read_named_file([&] { return twin::read_surface_mesh(file); });
    mesh.vertices = s.positions;
    mesh.triangles = s.triangles;
  } else {
    mesh = inline_mesh(m);
  }
  if (const auto n = m.optional("name")) mesh.name = n->string();
  if (const auto a = m.optional("albedo")) mesh.albedo = albedo(*a);
  return mesh;
}

D415NoiseConfig read_noise(const JsonField& n) {
  n.only_keys({"sigma_at_1m_mm", "bias_at_1m_mm", "grazing_limit_deg", "edge_jump_m", "min_range_m", "max_range_m",
               "dropout_fraction", "stereo_shadow", "shadow_tolerance_m", "color_noise_counts", "ambient"});
  D415NoiseConfig c;
  c.sigma_at_1m_mm = get(n, "sigma_at_1m_mm", c.sigma_at_1m_mm, "mm");
  c.bias_at_1m_mm = get(n, "bias_at_1m_mm", c.bias_at_1m_mm, "mm");
  c.grazing_limit_deg = get(n, "grazing_limit_deg", c.grazing_limit_deg, "deg");
  c.edge_jump_m = get(n, "edge_jump_m", c.edge_jump_m, "m");
  c.min_range_m = get(n, "min_range_m", c.min_range_m, "m");
  c.max_range_m = get(n, "max_range_m", c.max_range_m, "m");
  c.dropout_fraction = get(n, "dropout_fraction", c.dropout_fraction, "fraction 0..1");
  c.stereo_shadow = get_bool(n, "stereo_shadow", c.stereo_shadow);
  c.shadow_tolerance_m = get(n, "shadow_tolerance_m", c.shadow_tolerance_m, "m");
  c.color_noise_counts = get(n, "color_noise_counts", c.color_noise_counts, "counts");
  c.ambient = get(n, "ambient", c.ambient, "fraction 0..1");
  if (c.sigma_at_1m_mm < 0) n["sigma_at_1m_mm"].fail("must be >= 0");
  if (c.dropout_fraction < 0 || c.dropout_fraction > 1) n["dropout_fraction"].fail("must be in 0..1");
  if (c.min_range_m < 0 || c.max_range_m <= c.min_range_m) n.fail("needs 0 <= min_range_m < max_range_m");
  return c;
}

D415FaultConfig read_faults(const JsonField& f) {
  f.only_keys({"drop_probability", "drop_every_nth", "drop_from_s", "drop_until_s", "frozen_from_s",
               "frozen_until_s", "frozen_sequence_advances", "dead_from_s", "dead_until_s", "stale_from_s",
               "stale_until_s", "stale_mode", "stale_lag_s", "bumped_from_s", "bumped_until_s", "bump_m"});
  D415FaultConfig c;
  c.drop_probability = get(f, "drop_probability", c.drop_probability, "probability 0..1");
  if (c.drop_probability < 0 || c.drop_probability > 1) f["drop_probability"].fail("must be in 0..1");
  if (const auto n = f.optional("drop_every_nth")) c.drop_every_nth = n->positive_integer();
  c.drop_from_s = get(f, "drop_from_s", c.drop_from_s, "s");
  c.drop_until_s = get(f, "drop_until_s", c.drop_until_s, "s");
  c.frozen_from_s = get(f, "frozen_from_s", c.frozen_from_s, "s");
  c.frozen_until_s = get(f, "frozen_until_s", c.frozen_until_s, "s");
  c.frozen_sequence_advances = get_bool(f, "frozen_sequence_advances", c.frozen_sequence_advances);
  c.dead_from_s = get(f, "dead_from_s", c.dead_from_s, "s");
  c.dead_until_s = get(f, "dead_until_s", c.dead_until_s, "s");
  c.stale_from_s = get(f, "stale_from_s", c.stale_from_s, "s");
  c.stale_until_s = get(f, "stale_until_s", c.stale_until_s, "s");
  if (const auto m = f.optional("stale_mode")) {
    const std::string s = m->string();
    if (s == "stopped") c.stale_mode = StaleMode::kStopped;
    else if (s == "lagging") c.stale_mode = StaleMode::kLagging;
    else m->fail("must be \"stopped\" or \"lagging\", got \"" + s + "\"");
  }
  if (const auto l = f.optional("stale_lag_s")) c.stale_lag_s = l->positive("s");
  c.bumped_from_s = get(f, "bumped_from_s", c.bumped_from_s, "s");
  c.bumped_until_s = get(f, "bumped_until_s", c.bumped_until_s, "s");
  if (const auto b = f.optional("bump_m")) {
    if (b->array_size() != 3) b->fail("must be [x, y, z] (m, camera frame)");
    c.bump_x_m = (*b)[0].number("m");
    c.bump_y_m = (*b)[1].number("m");
    c.bump_z_m = (*b)[2].number("m");
  }
  return c;
}

}  // namespace

SimulatedD415Options load_d415_scene_file(const std::string& path) {
  const nlohmann::json doc = JsonField::parse_file(path);
  const JsonField root(doc, path);
  root.only_keys({"meshes", "boxes", "floor", "light_direction", "background", "seed", "clock", "noise", "faults"});
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  auto scene = std::make_shared<RenderScene>();
  const JsonField meshes = root["meshes"];
  for (std::size_t i = 0; i < meshes.array_size(); ++i) scene->meshes.push_back(read_mesh(meshes[i], dir));
  if (const auto boxes = root.optional("boxes")) {
    for (std::size_t i = 0; i < boxes->array_size(); ++i) {
      const JsonField b = (*boxes)[i];
      b.only_keys({"name", "min_m", "max_m", "albedo"});
      const Eigen::Vector3d lo = b["min_m"].vec3("m"), hi = b["max_m"].vec3("m");
      if ((hi - lo).minCoeff() <= 0.0) b.fail("needs max_m > min_m in every coordinate");
      scene->meshes.push_back(make_box_mesh(b.has("name") ? b["name"].string() : "box", lo, hi,
                                            b.has("albedo") ? albedo(b["albedo"]) : Albedo(150, 120, 90)));
    }
  }
  if (const auto fl = root.optional("floor")) {
    fl->only_keys({"height_m", "albedo"});
    FloorPlane floor;
    floor.height_m = get(*fl, "height_m", 0.0, "m");
    if (const auto a = fl->optional("albedo")) floor.albedo = albedo(*a);
    scene->floor = floor;
  }
  if (const auto l = root.optional("light_direction")) {
    scene->light_direction_cell = l->vec3("(direction)");
    if (!(scene->light_direction_cell.norm() > 0.0)) l->fail("must not be zero");
  }
  if (const auto b = root.optional("background")) scene->background = albedo(*b);
  SimulatedD415Options options;
  if (const auto s = root.optional("seed")) {
    if (!s->json().is_number_unsigned()) s->fail("must be a non-negative integer");
    options.seed = s->json().get<std::uint64_t>();
  }
  if (const auto c = root.optional("clock")) {
    const std::string s = c->string();
    if (s == "simulated") options.clock = SimClock::kSimulated;
    else if (s == "wall") options.clock = SimClock::kWall;
    else if (s == "process") options.clock = SimClock::kProcess;
    else c->fail("must be \"simulated\", \"wall\" or \"process\", got \"" + s + "\"");
  }
  if (const auto n = root.optional("noise")) options.noise = read_noise(*n);
  if (const auto f = root.optional("faults")) options.faults = read_faults(*f);
  std::shared_ptr<const RenderScene> fixed = std::move(scene);
  options.scene = [fixed](double) { return fixed; };
  return options;
}

D415NoiseConfig read_d415_noise(const twin::JsonField& noise) { return read_noise(noise); }

}  // namespace sim_hw
