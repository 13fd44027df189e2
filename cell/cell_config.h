#pragma once
// The cell config file (JSON) as the cell controller reads it. The "cameras" array belongs to
// drivers/camera_config_json.h and "arms"/"grippers" to drivers/cell_hardware_config.h; this
// file owns the other keys (every one optional unless marked required; unknown keys are errors):
//   "cell": {"lcm_url": "udpm://239.255.76.67:7667?ttl=0",  (LCM provider; --lcm overrides)
//            "clock": "wall",                 ("wall": real hardware; "sim": the fake world's
//                                              simulation clock, SIM_CLOCK, in lockstep: every
//                                              time the cell reads, pacing, watchdogs, frame and
//                                              message stamps, follows it, the world waits for
//                                              each cycle, and the twin steps in lockstep, so a
//                                              run repeats (drivers/sim_clock_client.h))
//            "sim_clock_timeout_s": 5,        (on "sim": no SIM_CLOCK for this long on the wall
//                                              -> SAFE_HOLD, s)
//            "cycle_hz": 15,                  (cycle rate, 1/s; the twin's dt = 1 / cycle_hz
//                                              per cycle its step spans)
//            "min_cameras": 2,                (fewer fresh cameras -> SAFE_HOLD; fewer than all
//                                              but at least this many -> DEGRADED)
//            "robot_status_timeout_ms": 250,  (an arm status older than this -> SAFE_HOLD, ms)
//            "camera_stale_ms": 500,          (a camera without a good frame for this long is
//                                              not fresh, ms)
//            "startup_timeout_s": 30,         (the whole start-up sequence, s)
//            "camera_startup_timeout_s": 5,   (each camera's first frame, s)
//            "arm_status_timeout_s": 2,       (each arm's first IIWA_STATUS at start-up, s)
//            "hold_tolerance_m": 0.02,        (a gripper must be this close to its planned
//                                              hold position at start-up, m)
//            "move_speed_m_s": 0.05,          (jaw speed of "move" actions, m/s, <= 0.05)
//            "joint_speed_scale": 0.25,       (fraction of the iiwa joint velocity limits)
//            "release_timeout_s": 2,          (no gripper status after a release command for
//                                              this long: the twin releases anyway, s)
//            "twin_lockstep": false,          (true: every cycle waits for the twin's step;
//                                              false: a cycle never waits, a step that is still
//                                              running is taken up by a later cycle, and the
//                                              next step covers the cycles it spanned)
//            "twin_priority": "normal",       ("idle": the twin's worker thread runs under
//                                              Linux SCHED_IDLE, on the CPU the cycle's
//                                              threads leave, preempted when they wake: for a
//                                              machine that runs the cell alone, since any
//                                              other busy process starves the twin;
//                                              "normal": at the cycle's own priority)
//            "twin_background_factorization": true},  (false: the twin's steps factorise on
//                                              the twin's own thread; true: a third thread
//                                              factorises the next step's Hessian while the
//                                              sheet moves, twin/solvers/implicit_stepper.h)
//   "twin": {"material_file": "composite.json",   (required; relative to this file)
//            "sheet": {...}},                      (required; twin/trials/sheet_spec.h; without a
//                                                    "placement" the flat start is centred under
//                                                    the plan's hold positions)
//   "job": {"plan_file": "plan.json",              (required; twin/trials/grasp_plan.h)
//           "experiment_file": "experiment.json"}, (optional; cell/experiment_file.h)
//   "tracker": {...} | "tracker.json"              (optional; tracking/tracker_config_json.h,
//                                                    inline or a file relative to this file)
//   "learning": {"record_states": true,            (keep the settled states the cameras see,
//                                                    cell/learning/settled_state.h)
//                "calibrate": true,                 (fit the material to them in the background
//                                                    and adopt it when it predicts a held-out
//                                                    state better: in_situ_calibration.h)
//                "window_s": 2, "min_still_s": 3,   (a settled state: the grasps still for
//                                                    min_still_s, then window_s of tracked cycles
//                                                    averaged, s)
//                "max_states": 16,                  (states kept; the oldest go first)
//                "min_gain": 0.1,                   (the held-out error must fall by this fraction)
//                "max_evaluations": 12,             (of each fit)
//                "parameters": ["tensile_N_m", "shear_N_m", "bending_Nm"],  (fitted, by the
//                                                    names of material files)
//                "diagnose": true,                  (after each calibration, name and add a
//                                                    missing effect: in_situ_diagnosis.h)
//                "diagnosis_effects": ["clamp_grip", ...],  (candidates; default every one a
//                                                    cell's states can carry)
//                "diagnosis_noise_mm": 2.0,         (the tracker's error per coordinate, mm;
//                                                    default: estimated from the states)
//                "diagnosis_max_evaluations": 12,   (of its base fit and of each start of a refit)
//                "follow_branches": true,           (re-seed the twin from a settled state it
//                                                    misses by more than reseed_min_error_m when
//                                                    that brings it nearer by reseed_min_gain)
//                "reseed_min_error_m": 0.005, "reseed_min_gain": 0.3,
//                "priority": "idle"}                ("idle": calibrations and branch candidates run
//                                                    under SCHED_IDLE, on CPU nothing else wants;
//                                                    "normal": beside the cycle, which they then
//                                                    slow down)
// Paths are relative to the config file's folder. Errors throw std::invalid_argument (or
// std::runtime_error for an unreadable file) naming the file and the field.
#include <string>
#include <vector>

#include "cell/background_worker.h"
#include "cell/learning/in_situ_calibration.h"
#include "cell/learning/in_situ_diagnosis.h"
#include "cell/learning/settled_state.h"
#include "drivers/cell_hardware_config.h"
#include "drivers/depth_camera.h"
#include "drivers/sim_clock_client.h"
#include "tracking/sheet_tracker.h"
#include "twin/trials/sheet_spec.h"

namespace cell {

struct CellSettings {
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  drivers::ClockSource clock = drivers::ClockSource::kWall;
  double sim_clock_timeout_s = 5.0;
  double cycle_hz = 15.0;
  int min_cameras = 2;
  double robot_status_timeout_ms = 250.0;
  double camera_stale_ms = 500.0;
  double startup_timeout_s = 30.0;
  double camera_startup_timeout_s = 5.0;
  double arm_status_timeout_s = 2.0;
  double hold_tolerance_m = 0.02;
  double move_speed_m_s = 0.05;
  double joint_speed_scale = 0.25;
  double release_timeout_s = 2.0;
  bool twin_lockstep = false;
  WorkerPriority twin_priority = WorkerPriority::kNormal;
  bool twin_background_factorization = true;
};

struct LearningSettings {
  bool record_states = true;
  bool calibrate = true;
  learning::SettleOptions settle;
  int max_states = 16;
  learning::CalibrationOptions calibration;
  bool diagnose = true;
  learning::DiagnosisOptions diagnosis;
  bool follow_branches = true;
  double reseed_min_error_m = 0.005;
  double reseed_min_gain = 0.3;
  WorkerPriority priority = WorkerPriority::kIdle;
};

struct CellConfig {
  std::string path;  // the file read
  CellSettings cell;
  std::string material_file;  // absolute or relative to the working directory
  twin::SheetSpec sheet;
  bool sheet_placement_given = false;
  std::string plan_file;
  std::string experiment_file;  // empty: none
  tracking::TrackerConfig tracker;
  LearningSettings learning;
  std::vector<drivers::CameraConfig> cameras;
  drivers::CellHardwareConfig hardware;
};

CellConfig read_cell_config(const std::string& path);

}  // namespace cell
