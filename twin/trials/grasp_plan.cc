#include "twin/trials/grasp_plan.h"

#include <cmath>
#include <set>

#include "twin/base/atomic_file.h"
#include "twin/base/json_field.h"

namespace twin {

int GraspPlan::index_of(const std::string& gripper) const {
  for (std::size_t i = 0; i < grasps.size(); ++i) {
    if (grasps[i].gripper == gripper) return static_cast<int>(i);
  }
  return -1;
}

std::vector<ClampSpec> GraspPlan::clamp_specs() const {
  std::vector<ClampSpec> specs;
  for (const Grasp& g : grasps) specs.push_back(g.clamp);
  return specs;
}

GraspPlan grasp_plan_from_json(const nlohmann::json& j, const std::string& source) {
  const JsonField f(j, source);
  f.only_keys({"grasps", "predicted_sag_m", "feasible", "note"});
  GraspPlan plan;
  const JsonField grasps = f["grasps"];
  if (grasps.array_size() == 0) grasps.fail("must list at least one grasp");
  std::set<std::string> names;
  for (std::size_t i = 0; i < grasps.array_size(); ++i) {
    const JsonField g = grasps[i];
    g.only_keys({"gripper", "material_point_m", "grip_radius_m", "hold_position_m"});
    Grasp grasp;
    grasp.gripper = g["gripper"].string();
    if (grasp.gripper.empty()) g["gripper"].fail("must not be empty");
    if (!names.insert(grasp.gripper).second) g["gripper"].fail("repeats gripper '" + grasp.gripper + "'");
    grasp.clamp.id = grasp.gripper;
    grasp.clamp.material_point_m = g["material_point_m"].vec2("m");
    grasp.clamp.grip_radius_m = kDefaultGripRadiusM;
    if (auto r = g.optional("grip_radius_m")) grasp.clamp.grip_radius_m = r->non_negative("m");
    grasp.hold_position_m = g["hold_position_m"].vec3("m");
    plan.grasps.push_back(grasp);
  }
  if (auto s = f.optional("predicted_sag_m")) plan.predicted_sag_m = s->number("m");
  if (auto b = f.optional("feasible")) {
    if (!b->json().is_boolean()) b->fail("must be true or false");
    plan.feasible = b->json().get<bool>();
  }
  if (auto n = f.optional("note")) plan.note = n->string();
  return plan;
}

GraspPlan read_grasp_plan(const std::string& path) {
  return grasp_plan_from_json(JsonField::parse_file(path), path);
}

nlohmann::json grasp_plan_to_json(const GraspPlan& plan) {
  nlohmann::json grasps = nlohmann::json::array();
  for (const Grasp& g : plan.grasps) {
    const Vec2& uv = g.clamp.material_point_m;
    const Vec3& p = g.hold_position_m;
    grasps.push_back({{"gripper", g.gripper},
                      {"material_point_m", {uv.x(), uv.y()}},
                      {"grip_radius_m", g.clamp.grip_radius_m},
                      {"hold_position_m", {p.x(), p.y(), p.z()}}});
  }
  nlohmann::json j = {{"grasps", grasps}, {"feasible", plan.feasible}, {"note", plan.note}};
  if (std::isfinite(plan.predicted_sag_m)) j["predicted_sag_m"] = plan.predicted_sag_m;
  return j;
}

void write_grasp_plan(const GraspPlan& plan, const std::string& path) {
  const nlohmann::json j = grasp_plan_to_json(plan);
  write_file_atomically(path, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

}  // namespace twin
