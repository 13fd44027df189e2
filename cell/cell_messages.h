#pragma once
// The cell's outgoing LCM messages built from its state: sheet states (observed, predicted),
// the prediction error, camera status and cell state. Pure functions, no bus.
#include <cstdint>
#include <string>
#include <vector>

#include <prepreg_lcm/camera_status_t.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/grasp_plan_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>

#include "cell/watchdog.h"
#include "drivers/cell_hardware_config.h"
#include "drivers/depth_camera.h"
#include "tracking/sheet_tracker.h"
#include "twin/trials/grasp_plan.h"
#include "twin/base/types.h"

namespace cell {

// Predicted sheet: the twin's positions (3n), no observed flags, coverage 1.
prepreg_lcm::sheet_state_t predicted_sheet(std::int64_t utime, std::int64_t cycle, const twin::VecX& x);
// Observed sheet: the tracked vertices with their observed flags and the tracker's coverage.
prepreg_lcm::sheet_state_t observed_sheet(std::int64_t utime, std::int64_t cycle,
                                          const tracking::TrackResult& r);

// Vertex-to-vertex error over the observed vertices (the message's definition): tracked minus
// predicted per vertex, NaN where not observed; mean, max, score = mean + 0.5 max.
struct VertexError {
  int compared = 0;
  double mean_m = 0, max_m = 0;
  std::vector<float> per_vertex_m;
};
VertexError vertex_error(const tracking::TrackResult& r);

prepreg_lcm::prediction_error_t prediction_error(std::int64_t utime, std::int64_t cycle,
                                                 std::int64_t frames_utime,
                                                 std::int64_t prediction_utime, const VertexError& e);

prepreg_lcm::camera_status_t camera_status(std::int64_t utime, const std::string& name,
                                           const drivers::CameraHealth& health, bool stale,
                                           bool frozen, std::int64_t last_frame_utime);

struct CellStatus {
  CellState state = CellState::kStarting;
  std::string reason;
  std::int64_t cycle = -1;
  bool cameras_ok = false, tracker_ok = false, twin_ok = false, robots_ok = false, grippers_ok = false;
  int cameras_fresh = 0, cameras = 0;
  int twin_reseeds = 0;  // branch following (cell_learning.cc)
};
prepreg_lcm::cell_state_t cell_state(std::int64_t utime, const CellStatus& s);

// The plan as published on GRASP_PLAN (arm names from the cell's grippers; the gripper's own
// name, e.g. "MANUAL", for one the operator holds).
prepreg_lcm::grasp_plan_t grasp_plan_message(std::int64_t utime, std::int64_t plan_id,
                                             const twin::GraspPlan& plan,
                                             const drivers::CellHardwareConfig& hardware);

}  // namespace cell
