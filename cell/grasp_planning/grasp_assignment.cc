#include "cell/grasp_planning/grasp_assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "drivers/iiwa_inverse_kinematics.h"

namespace cell {

std::vector<twin::Grasp> assign_grippers(const std::vector<std::string>& grippers,
                                         const std::vector<twin::Vec2>& points_uv_m,
                                         const std::vector<twin::Vec3>& holds_m, double grip_radius_m,
                                         const drivers::CellHardwareConfig* cell) {
  const std::size_t n = grippers.size();
  if (points_uv_m.size() != n || holds_m.size() != n) {
    throw std::invalid_argument("assign_grippers: one point and one hold per gripper expected");
  }
  // arms[g]: the arm carrying gripper g, or null (operator).
  std::vector<const drivers::ArmConfig*> arms(n, nullptr);
  if (cell) {
    for (std::size_t g = 0; g < n; ++g) {
      const drivers::GripperConfig* gc = cell->find_gripper(grippers[g]);
      if (!gc) throw std::invalid_argument("gripper '" + grippers[g] + "' is not in the cell config");
      if (!gc->arm.empty()) arms[g] = cell->find_arm(gc->arm);
    }
  }
  // order[g] = index of the point gripper g takes.
  std::vector<int> order(n), best(n);
  std::iota(order.begin(), order.end(), 0);
  best = order;
  double best_cost = std::numeric_limits<double>::infinity();
  do {
    double cost = 0.0;
    for (std::size_t g = 0; g < n; ++g) {
      if (arms[g]) cost += (holds_m[order[g]].head<2>() - arms[g]->base_in_cell.translation().head<2>()).norm();
    }
    if (cost < best_cost - 1e-12) {
      best_cost = cost;
      best = order;
    }
  } while (cell && std::next_permutation(order.begin(), order.end()));
  std::vector<twin::Grasp> grasps(n);
  for (std::size_t g = 0; g < n; ++g) {
    grasps[g].gripper = grippers[g];
    grasps[g].clamp.id = grippers[g];
    grasps[g].clamp.material_point_m = points_uv_m[best[g]];
    grasps[g].clamp.grip_radius_m = grip_radius_m;
    grasps[g].hold_position_m = holds_m[best[g]];
  }
  return grasps;
}

std::string check_reachability(const std::vector<twin::Grasp>& grasps,
                               const drivers::CellHardwareConfig& cell) {
  for (const twin::Grasp& g : grasps) {
    const drivers::GripperConfig* gc = cell.find_gripper(g.gripper);
    if (!gc || gc->arm.empty()) continue;
    const drivers::ArmConfig* arm = cell.find_arm(gc->arm);
    if (!arm) continue;  // the cell config reader guarantees it exists
    const drivers::IiwaArm kinematics = arm->arm();
    drivers::IkOptions options;
    options.restarts = 8;
    drivers::IkResult last;
    bool reached = false;
    for (int quarter = 0; quarter < 4 && !reached; ++quarter) {
      const Eigen::Isometry3d target = drivers::flange_pose_for_jaw(*arm, g.hold_position_m, quarter * M_PI / 2);
      last = drivers::solve_inverse_kinematics(kinematics, target, arm->home_rad, options);
      reached = last.status == drivers::IkStatus::kConverged;
    }
    if (!reached) {
      return fmt::format("arm {} cannot reach [{:.3f}, {:.3f}, {:.3f}] m: {} ({:.3f} m off)", arm->name,
                         g.hold_position_m.x(), g.hold_position_m.y(), g.hold_position_m.z(),
                         drivers::to_string(last.status), last.position_residual_m);
    }
  }
  return "";
}

}  // namespace cell
