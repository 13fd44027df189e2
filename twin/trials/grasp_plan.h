#pragma once
// Where the grippers hold a ply: the grasp plan file written by the grasp planner, read by the
// cell controller (its twin's clamps and the robots' targets) and by the fake-hardware world
// (the operator stand-in loads the ply into the grippers as planned). JSON:
//   {"grasps": [{"gripper": "LEFT",                  (gripper name from the cell config)
//                "material_point_m": [u, v],         (on the ply, m; u = weft, v = warp)
//                "grip_radius_m": 0.02,              (optional, default 0.02)
//                "hold_position_m": [x, y, z]}, ...],(jaw centre in the cell frame, m)
//    "predicted_sag_m": 0.12,                        (optional: the twin's sag below the grasps)
//    "feasible": true,                               (optional, default true)
//    "note": "..."}                                  (optional)
// Gripper names must be unique and at least one grasp given.
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "twin/model/clamp.h"

namespace twin {

struct Grasp {
  std::string gripper;
  ClampSpec clamp;  // id = gripper
  Vec3 hold_position_m = Vec3::Zero();
};

struct GraspPlan {
  std::vector<Grasp> grasps;
  double predicted_sag_m = std::numeric_limits<double>::quiet_NaN();
  bool feasible = true;
  std::string note;

  // Index of the grasp of this gripper, or -1.
  int index_of(const std::string& gripper) const;
  std::vector<ClampSpec> clamp_specs() const;
};

inline constexpr double kDefaultGripRadiusM = 0.02;

// Throws std::invalid_argument naming `source` and the field.
GraspPlan grasp_plan_from_json(const nlohmann::json& j, const std::string& source);
// Also throws std::runtime_error when the file cannot be read or is not JSON.
GraspPlan read_grasp_plan(const std::string& path);
nlohmann::json grasp_plan_to_json(const GraspPlan& plan);
// Written atomically (a crash leaves the old file whole).
void write_grasp_plan(const GraspPlan& plan, const std::string& path);

}  // namespace twin
