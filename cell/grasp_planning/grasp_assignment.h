#pragma once
// Which gripper takes which grasp point, and whether each arm can reach its hold.
//
// Without a cell config the goal's grippers take the points in ring order. With one, the
// assignment minimises the summed horizontal distance from each arm's base to its hold position
// (all permutations: at most 4! = 24); grippers without an arm (held by the operator, "MANUAL")
// take what is left. Reachability: inverse kinematics of the arm to the flange pose that puts
// the jaw centre on the hold position reaching straight down (drivers::flange_pose_for_jaw),
// with the jaw turned about the vertical by 0, 90, 180 or 270 degrees (the first that converges
// counts; seeded restarts, so repeatable).
#include <optional>
#include <string>
#include <vector>

#include "drivers/cell_hardware_config.h"
#include "twin/trials/grasp_plan.h"

namespace cell {

// grasps[i].gripper is set; material points and hold positions are kept in order.
// Throws std::invalid_argument when a gripper of the goal is not in the cell config.
std::vector<twin::Grasp> assign_grippers(const std::vector<std::string>& grippers,
                                         const std::vector<twin::Vec2>& points_uv_m,
                                         const std::vector<twin::Vec3>& holds_m, double grip_radius_m,
                                         const drivers::CellHardwareConfig* cell);

// "" when every armed gripper reaches its hold, else e.g. "arm LEFT cannot reach [..]: ...".
std::string check_reachability(const std::vector<twin::Grasp>& grasps,
                               const drivers::CellHardwareConfig& cell);

}  // namespace cell
