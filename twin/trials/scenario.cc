#include "twin/trials/scenario.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "twin/model/clamp_json.h"
#include "twin/base/json_field.h"
#include "twin/mesh/mesh_io.h"
#include "twin/trials/sheet_spec.h"

namespace twin {
namespace {

std::string resolve(const std::string& base, const std::string& path) {
  const std::filesystem::path p(path);
  return p.is_absolute() || base.empty() ? path : (std::filesystem::path(base) / p).string();
}

void read_clamps(const JsonField& f, Scenario& s) {
  for (std::size_t i = 0; i < f.array_size(); ++i) {
    s.clamps.push_back(read_clamp_spec(f[i]));
  }
}

ClampPose read_pose(const JsonField& f, const ClampPose& previous, const SheetPlacement& placement) {
  ClampPose pose = previous;
  pose.engaged = true;
  if (f.is_string()) {
    if (f.string() != "released") f.fail("must be [x, y, z] (m), an object or \"released\"");
    pose.engaged = false;
    return pose;
  }
  if (f.is_array()) {
    pose.position_m = f.vec3("m");
    if (!previous.engaged) pose.rotation = placement.rotation;
    return pose;
  }
  f.only_keys({"position_m", "rotation_deg"});
  pose.position_m = f["position_m"].vec3("m");
  pose.rotation = f.has("rotation_deg") ? rotation_from_degrees(f["rotation_deg"].vec3("deg"))
                                        : placement.rotation;
  return pose;
}

void read_stages(const JsonField& f, Scenario& s, const ClampSet& clamps) {
  std::vector<ClampPose> poses(s.clamps.size());
  for (ClampPose& p : poses) p.engaged = false;
  if (f.array_size() == 0) f.fail("must list at least one stage");
  for (std::size_t i = 0; i < f.array_size(); ++i) {
    const JsonField st = f[i];
    st.only_keys({"id", "clamps"});
    Stage stage;
    stage.id = st.has("id") ? st["id"].string() : std::to_string(i + 1);
    // Stage ids name output files (stage_<id>.ply): keep them to plain, unique file-name words.
    const bool plain = !stage.id.empty() && stage.id != "." && stage.id != ".." &&
                       stage.id.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") == std::string::npos;
    if (!plain) st.fail_child("id", "must be letters, digits, '_', '.' or '-' (it names a file), got \"" + stage.id + "\"");
    for (const Stage& earlier : s.stages) {
      if (earlier.id == stage.id) st.fail_child("id", "\"" + stage.id + "\" is used by an earlier stage");
    }
    const JsonField c = st["clamps"];
    if (!c.is_object()) c.fail("must be an object {\"clamp id\": pose, ...}");
    for (const auto& item : c.json().items()) {
      int index = -1;
      try {
        index = clamps.index_of(item.key());
      } catch (const std::invalid_argument&) {
        c[item.key()].fail("names no clamp of the 'clamps' list");
      }
      poses[index] = read_pose(c[item.key()], poses[index], s.placement);
    }
    if (std::none_of(poses.begin(), poses.end(), [](const ClampPose& p) { return p.engaged; })) {
      st.fail_child("clamps", "leave no clamp holding the sheet: a free sheet has no static equilibrium");
    }
    stage.poses = poses;
    s.stages.push_back(stage);
  }
}

void read_solver(const JsonField& f, ContinuationOptions& o) {
  f.only_keys({"increment_m", "increment_deg", "residual_tolerance", "max_iterations"});
  // Bounded so the increment count stays an int and a run stays finite.
  if (auto v = f.optional("increment_m")) {
    o.increment_m = v->positive("m");
    if (o.increment_m < 1e-4) v->fail("must be at least 1e-4 m");
  }
  if (auto v = f.optional("increment_deg")) {
    o.increment_rad = v->positive("deg") * M_PI / 180.0;
    if (o.increment_rad < 1e-4) v->fail("must be at least 0.006 deg");
  }
  if (auto v = f.optional("residual_tolerance")) o.newton.residual_tolerance = v->positive("(relative)");
  if (auto v = f.optional("max_iterations")) o.newton.max_iterations = v->positive_integer();
}

}  // namespace

Scenario scenario_from_json(const nlohmann::json& j, const std::string& source,
                            const std::string& base_directory) {
  const JsonField f(j, source);
  f.only_keys({"sheet", "material", "material_file", "clamps", "stages", "solver"});
  Scenario s;
  s.source = source;
  SheetSpec sheet = read_sheet_spec(f["sheet"], base_directory);
  s.mesh = std::move(sheet.mesh);
  s.mesh_description = std::move(sheet.description);
  s.placement = sheet.placement;
  if (f.has("material") == f.has("material_file")) {
    f.fail_child("material", "or 'material_file' must be given, exactly one of them");
  }
  if (auto m = f.optional("material")) {
    s.material = material_from_json(m->json(), source + " (material)");
  } else {
    const JsonField file = f["material_file"];
    s.material = file.read_named_file([&] { return read_material_file(resolve(base_directory, file.string())); });
  }
  read_clamps(f["clamps"], s);
  ClampSet clamps;
  try {
    clamps = ClampSet(s.mesh, s.clamps);
  } catch (const std::invalid_argument& e) {
    f["clamps"].fail(std::string("are not valid: ") + e.what());
  }
  read_stages(f["stages"], s, clamps);
  if (auto solver = f.optional("solver")) read_solver(*solver, s.solver);
  return s;
}

Scenario read_scenario_file(const std::string& path) {
  return scenario_from_json(JsonField::parse_file(path), path,
                            std::filesystem::path(path).parent_path().string());
}

}  // namespace twin
