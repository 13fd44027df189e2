#pragma once
// Candidate grasp sets for the planner: which material points of the ply the grippers take and
// how far their holds are drawn together.
//
// Points lie on rings inset from the ply's edges (its bounding rectangle in material
// coordinates, inset by each of the search's insets, points about ring_spacing_m apart, corners
// included; points off a non-rectangular ply are dropped). On each ring, for N grippers: the
// four corners (N = 4), every rotation of N points evenly spaced along the ring, and
// random_candidates seeded random sets of N points (no two neighbours on the ring). Each
// point set is combined with every slack factor. Duplicates are removed. Deterministic.
//
// Hold positions come from the ply's flat layout above the tool (ply centre over the tool
// centre, u axis along the tool's yaw, at the hold height), drawn towards the grasps' centroid:
// hold = c + (1 - slack) (flat - c). Slack lets the ply hang in a shallow trough between the
// grasps instead of being pulled flat (which stretches it and loads the grippers).
#include <string>
#include <vector>

#include "cell/grasp_planning/grasp_goal.h"

namespace cell {

struct GraspCandidate {
  std::vector<twin::Vec2> points_uv_m;  // one per gripper, in ring order
  double inset_m = 0.0;
  double slack = 0.0;
  std::string kind;                     // "corners", "even", "random"
};

// Points on the ring inset by inset_m, in counter-clockwise order from the (min u, min v) corner.
std::vector<twin::Vec2> ring_points(const twin::SheetMesh& mesh, double inset_m, double spacing_m);

std::vector<GraspCandidate> generate_candidates(const twin::SheetMesh& mesh, int grippers,
                                                const GraspSearchOptions& search);

// Where material point uv lies in the flat layout above the tool (cell frame, m).
twin::Vec3 flat_layout_position(const twin::SheetMesh& mesh, const GraspGoal& goal, const twin::Vec2& uv);

// Hold positions (cell frame, m) of the candidate's points, in the same order.
std::vector<twin::Vec3> hold_positions(const twin::SheetMesh& mesh, const GraspGoal& goal,
                                       const GraspCandidate& candidate);

}  // namespace cell
