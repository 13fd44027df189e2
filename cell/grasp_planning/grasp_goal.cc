#include "cell/grasp_planning/grasp_goal.h"

#include <cmath>
#include <filesystem>
#include <set>

#include "twin/base/json_field.h"

namespace cell {
namespace {

using twin::JsonField;

std::string resolve(const std::string& base, const std::string& file) {
  const std::filesystem::path p(file);
  return p.is_absolute() || base.empty() ? p.string() : (std::filesystem::path(base) / p).string();
}

std::vector<double> positive_list(const JsonField& f, const char* unit) {
  std::vector<double> values;
  if (f.array_size() == 0) f.fail("must list at least one value");
  for (std::size_t i = 0; i < f.array_size(); ++i) values.push_back(f[i].positive(unit));
  return values;
}

GraspSearchOptions read_search(const JsonField& f) {
  GraspSearchOptions s;
  f.only_keys({"inset_m", "ring_spacing_m", "slack_factors", "random_candidates",
               "screening_triangles", "finalists", "refine_evaluations", "seed"});
  if (auto v = f.optional("inset_m")) s.inset_m = positive_list(*v, "m");
  if (auto v = f.optional("ring_spacing_m")) s.ring_spacing_m = v->positive("m");
  if (auto v = f.optional("slack_factors")) {
    s.slack_factors.clear();
    if (v->array_size() == 0) v->fail("must list at least one value");
    for (std::size_t i = 0; i < v->array_size(); ++i) {
      const double k = (*v)[i].non_negative("(share of the flat distance to the centre)");
      if (k >= 0.5) (*v)[i].fail("must be below 0.5 (the share the holds are drawn in)");
      s.slack_factors.push_back(k);
    }
  }
  if (auto v = f.optional("random_candidates")) {
    // 0 is allowed (structured candidates only).
    if (!v->json().is_number_integer() || v->json().get<long long>() < 0 ||
        v->json().get<long long>() > 100000) {
      v->fail("must be an integer from 0 to 100000");
    }
    s.random_candidates = v->json().get<int>();
  }
  if (auto v = f.optional("screening_triangles")) s.screening_triangles = v->positive_integer();
  if (auto v = f.optional("finalists")) {
    if (v->json().is_string() && v->json().get<std::string>() == "all") {
      s.finalists = 0;
    } else if (v->json().is_number_integer() && v->json().get<long long>() > 0 &&
               v->json().get<long long>() <= 100000) {
      s.finalists = v->json().get<int>();
    } else {
      v->fail("must be \"all\" or an integer from 1 to 100000");
    }
  }
  if (auto v = f.optional("refine_evaluations")) {
    if (!v->json().is_number_integer() || v->json().get<long long>() < 0 || v->json().get<long long>() > 10000) {
      v->fail("must be an integer from 0 (no refinement) to 10000");
    }
    s.refine_evaluations = v->json().get<int>();
  }
  if (auto v = f.optional("seed")) s.seed = static_cast<unsigned>(v->positive_integer());
  return s;
}

ToolSpec read_tool(const JsonField& f) {
  ToolSpec t;
  f.only_keys({"centre_m", "top_z_m", "size_m", "yaw_deg"});
  t.centre_m = f["centre_m"].vec2("m");
  t.top_z_m = f["top_z_m"].number("m");
  if (auto s = f.optional("size_m")) {
    t.size_m = s->vec2("m");
    if (!(t.size_m.x() > 0 && t.size_m.y() > 0)) s->fail("must be two positive sizes in m");
    t.has_size = true;
  }
  if (auto y = f.optional("yaw_deg")) t.yaw_rad = y->number("deg") * M_PI / 180.0;
  return t;
}

}  // namespace

GraspGoal grasp_goal_from_json(const nlohmann::json& j, const std::string& source,
                               const std::string& base) {
  const JsonField f(j, source);
  f.only_keys({"sheet", "material_file", "tool", "hold_z_m", "max_sag_m", "min_clearance_m",
               "folds", "grippers", "grip_radius_m", "search"});
  GraspGoal g;
  g.source = source;
  g.sheet = twin::read_sheet_spec(f["sheet"], base);
  g.sheet_json = f["sheet"].json();
  g.sheet_base_directory = base;
  g.material = twin::read_material_file(resolve(base, f["material_file"].string()));
  g.tool = read_tool(f["tool"]);
  g.hold_z_m = f["hold_z_m"].number("m");
  if (g.hold_z_m <= g.tool.top_z_m) f["hold_z_m"].fail("must be above tool.top_z_m");
  g.max_sag_m = f["max_sag_m"].positive("m");
  if (auto c = f.optional("min_clearance_m")) g.min_clearance_m = c->non_negative("m");
  if (auto folds = f.optional("folds")) {
    folds->only_keys({"min_bend_radius_m", "max_overturned_fraction"});
    if (auto r = folds->optional("min_bend_radius_m")) g.folds.min_bend_radius_m = r->non_negative("m");
    if (auto o = folds->optional("max_overturned_fraction")) {
      g.folds.max_overturned_fraction = o->non_negative("(share of the area)");
      if (g.folds.max_overturned_fraction > 1.0) o->fail("must be a share from 0 to 1");
    }
  }
  const JsonField grippers = f["grippers"];
  if (grippers.array_size() < 2 || grippers.array_size() > 4) {
    grippers.fail("must list 2 to 4 gripper names");
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < grippers.array_size(); ++i) {
    const std::string name = grippers[i].string();
    if (name.empty() || !seen.insert(name).second) grippers[i].fail("must be a unique, non-empty name");
    g.grippers.push_back(name);
  }
  if (auto r = f.optional("grip_radius_m")) g.grip_radius_m = r->non_negative("m");
  if (auto s = f.optional("search")) g.search = read_search(*s);
  return g;
}

GraspGoal read_grasp_goal(const std::string& path) {
  const nlohmann::json j = JsonField::parse_file(path);
  return grasp_goal_from_json(j, path, std::filesystem::path(path).parent_path().string());
}

twin::SheetMesh screening_mesh(const GraspGoal& goal) {
  if (goal.sheet_json.contains("mesh_file")) return goal.sheet.mesh;
  nlohmann::json coarse = goal.sheet_json;
  coarse.erase("edge_length_m");
  coarse["target_triangles"] = goal.search.screening_triangles;
  return twin::read_sheet_spec(JsonField(coarse, goal.source, "sheet"), goal.sheet_base_directory).mesh;
}

}  // namespace cell
