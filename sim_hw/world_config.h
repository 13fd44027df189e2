#pragma once
// The fake-hardware world's own config file (`cell_world --world WORLD.json`), read together with
// the cell config (arms, grippers, cameras' modes, job.plan_file). It holds what the cell must
// not know: the true sheet and material, the true camera poses, how the devices are emulated.
//   {"sheet": {...},                       (twin/trials/sheet_spec.h; the true sheet's own mesh)
//    "material_file": "composite_truth.json",   (relative to this file; twin material file)
//    "physics": {"dt_s": 0.0333, "truth_hz": 5,      (step, s; SIM_SHEET_TRUTH rate, Hz)
//                "truth_model": "independent",       (or "twin": the true sheet's physics,
//                "grid_spacing_m": 0.04},             true_sheet_physics.h; independent grid, m)
//    "arms": {"status_hz": 100},                     (IIWA_STATUS_<ARM> rate = follow rate, Hz)
//    "grippers": {"status_hz": 50, "capture_distance_m": 0.03,  (CLOSE grips within this, m)
//                 "grip_radius_m": 0.02, "open_width_m": 0.06}, (clamp patch, m; jaw opening, m)
//    "scene": {"floor_height_m": 0.0,                (optional; absent = no floor)
//              "boxes": [{"name": "table", "min_m": [...], "max_m": [...]}]},  (cell frame, m)
//    "cameras": [{"name": "cam_front",               (every camera of the cell config, once)
//                 "camera_to_cell": {...},           (TRUE pose, drivers/pose_json.h)
//                 "noise": {...},                    (optional, d415_scene_file.h "noise")
//                 "seed": 1,                         (optional, noise random seed)
//                 "node_prefix": "prepreg_world_cam_front",   (shm nodes <prefix>_depth/_color)
//                 "depth_device": "/dev/video0", "color_device": "/dev/video1"}]}
// The device paths must be the ones of the camera's uri in the cell config ("depth=...,color=...").
// Every section but "sheet", "material_file" and "cameras" is optional (defaults as above).
// Unknown keys are rejected; errors throw std::invalid_argument naming the file and the field.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "drivers/cell_hardware_config.h"
#include "drivers/depth_camera.h"
#include "sim_hw/d415_error_model.h"
#include "sim_hw/render_scene.h"
#include "sim_hw/true_sheet_physics.h"
#include "twin/trials/grasp_plan.h"
#include "twin/model/material.h"
#include "twin/trials/sheet_spec.h"

namespace sim_hw {

struct WorldCamera {
  drivers::CameraConfig config;  // the cell config's camera, camera_to_cell replaced by the truth
  D415NoiseConfig noise;
  std::uint64_t seed = 1;
  std::string node_prefix;
  std::string depth_device, color_device;
};

struct WorldConfig {
  // From the world file.
  twin::SheetSpec sheet;
  twin::Material material;
  double dt_s = 1.0 / 30.0;
  double truth_hz = 5.0;
  TrueSheetOptions truth;  // which physics the true sheet follows
  double arm_status_hz = 100.0;
  double gripper_status_hz = 50.0;
  double capture_distance_m = 0.03;
  double grip_radius_m = twin::kDefaultGripRadiusM;
  double open_width_m = 0.06;
  RenderScene static_scene;  // boxes and floor (no sheet)
  std::vector<WorldCamera> cameras;
  // From the cell config.
  drivers::CellHardwareConfig hardware;
  twin::GraspPlan plan;  // job.plan_file
  std::string plan_path;
};

// Reads both files; throws std::invalid_argument / std::runtime_error naming the file and field.
WorldConfig read_world_config(const std::string& cell_config_path, const std::string& world_path);

}  // namespace sim_hw
