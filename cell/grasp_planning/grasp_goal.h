#pragma once
// What the grasp planner is asked for: hold this ply above this tool, sagging at most so much and
// without folds, with these 2-4 grippers. Goal file (JSON; relative paths are relative to it):
//   {"sheet": {...},                   (twin/trials/sheet_spec.h; its "placement" is not used: the planner
//                                       lays the ply out over the tool)
//    "material_file": "composite_identified.json",
//    "tool": {"centre_m": [x, y],      (cell frame, m: the flat ply's centre is laid out above it)
//             "top_z_m": 0.75,         (height of the tool's top surface, m)
//             "size_m": [w, h],        (optional: the tool's top rectangle, m; clearance is then
//                                       checked only for ply points above it)
//             "yaw_deg": 0},           (optional: the ply's u axis turned this far from cell x)
//    "hold_z_m": 1.0,                  (height of every grasp, m)
//    "max_sag_m": 0.25,                (sag = hold_z_m - lowest point of the ply, m: how far any
//                                       point hangs below the grasps)
//    "min_clearance_m": 0.05,          (optional, default 0: lowest ply point above the tool top)
//    "folds": {"min_bend_radius_m": 0.02,             (optional, see hang_evaluation.h)
//              "max_overturned_fraction": 0.0},
//    "grippers": ["LEFT", "RIGHT", "CENTER", "MANUAL"],   (2-4 names from the cell config)
//    "grip_radius_m": 0.02,            (optional)
//    "search": {...}}                  (optional, GraspSearchOptions below)
// Errors throw std::invalid_argument naming the file and the field.
#include <string>
#include <vector>

#include "twin/model/material.h"
#include "twin/trials/sheet_spec.h"

namespace cell {

struct ToolSpec {
  twin::Vec2 centre_m = twin::Vec2::Zero();
  double top_z_m = 0.0;
  bool has_size = false;
  twin::Vec2 size_m = twin::Vec2::Zero();
  double yaw_rad = 0.0;
};

// Physically, a fold is where the ply doubles over on itself: it is creased (fibres kink and the
// tacky resin sticks the ply to itself) and the part past the crease faces down.
struct FoldLimits {
  // No hinge bent to a radius below this (m). A mesh cannot show radii below about its edge
  // length / pi, so choose it above that of the screening mesh.
  double min_bend_radius_m = 0.02;
  // Largest share of the ply's area whose top side faces down (normal more than 30 degrees
  // below horizontal): hanging flaps are vertical (normal horizontal), a turned-over flap is not.
  double max_overturned_fraction = 0.0;
};

struct GraspSearchOptions {
  std::vector<double> inset_m = {0.05, 0.10, 0.15};  // candidate rings: this far inside the edges
  double ring_spacing_m = 0.10;                      // spacing of candidate points on a ring
  std::vector<double> slack_factors = {0.04, 0.08};  // holds drawn this share toward the centre
  int random_candidates = 12;                        // extra seeded random point sets per ring
  int screening_triangles = 400;                     // coarse mesh (rectangular plies only)
  // How many of the best screened are simulated again on the target mesh and ranked there;
  // 0 ("all" in the file, the default): every screened candidate, so the ranking is the target
  // mesh's (the cell twin's), not the screening mesh's rough one.
  int finalists = 0;
  int refine_evaluations = 0;                        // BOBYQA refinement of the best (0: none)
  unsigned seed = 1;
};

struct GraspGoal {
  std::string source;
  twin::SheetSpec sheet;           // target mesh
  nlohmann::json sheet_json;       // as given, to build the coarse screening mesh
  std::string sheet_base_directory;
  twin::Material material;
  ToolSpec tool;
  double hold_z_m = 1.0;
  double max_sag_m = 0.0;
  double min_clearance_m = 0.0;
  FoldLimits folds;
  std::vector<std::string> grippers;
  double grip_radius_m = 0.02;
  GraspSearchOptions search;
};

GraspGoal grasp_goal_from_json(const nlohmann::json& j, const std::string& source,
                               const std::string& base_directory);
// Also throws std::runtime_error when the file cannot be read or is not JSON.
GraspGoal read_grasp_goal(const std::string& path);

// The ply's mesh at about `triangles` triangles when it is a rectangle; the target mesh when it is
// a mesh file (which the planner cannot coarsen).
twin::SheetMesh screening_mesh(const GraspGoal& goal);

}  // namespace cell
