#pragma once
// Channel names of the cell's LCM bus, in one place so the cell, the fake world, the monitor and
// real drivers agree.
//
// Conventions:
// - Upper case, words joined by '_'.
// - Per-device channels end in _<DEVICE>: IIWA_COMMAND_<ARM>, IIWA_STATUS_<ARM>,
//   GRIPPER_COMMAND_<ARM>, GRIPPER_STATUS_<ARM>, CAMERA_STATUS_<CAMERA>. <ARM> and <CAMERA> are
//   the names from the cell configuration, upper-cased (letters, digits, '_').
// - The standard cell has three arms: LEFT and RIGHT (KUKA LBR iiwa 7 R800) and CENTER (LBR iiwa
//   14 R820), each with its own command/status pair, because an iiwa LCM driver serves one arm
//   and Drake's single-arm default names (IIWA_COMMAND, IIWA_STATUS) cannot tell arms apart. A real
//   driver is started with its command/status channel names set to the arm's pair.
// - LCM subscriptions treat the channel as a regular expression matched against the whole
//   name, so CAMERA_STATUS_.* subscribes to every camera.

#include <string>
#include <string_view>

namespace drivers::channels {

inline constexpr std::string_view kIiwaCommandPrefix = "IIWA_COMMAND_";  // + ARM, lcmt_iiwa_command
inline constexpr std::string_view kIiwaStatusPrefix = "IIWA_STATUS_";    // + ARM, lcmt_iiwa_status
inline constexpr std::string_view kGripperCommandPrefix = "GRIPPER_COMMAND_";  // gripper_command_t
inline constexpr std::string_view kGripperStatusPrefix = "GRIPPER_STATUS_";    // gripper_status_t
inline constexpr std::string_view kCameraStatusPrefix = "CAMERA_STATUS_";      // camera_status_t

inline constexpr std::string_view kSheetObserved = "SHEET_OBSERVED";    // sheet_state_t, tracker
inline constexpr std::string_view kSheetPredicted = "SHEET_PREDICTED";  // sheet_state_t, twin
inline constexpr std::string_view kPredictionError = "PREDICTION_ERROR";  // prediction_error_t
inline constexpr std::string_view kCellState = "CELL_STATE";              // cell_state_t
inline constexpr std::string_view kGraspPlan = "GRASP_PLAN";              // grasp_plan_t
inline constexpr std::string_view kCellCalibration = "CELL_CALIBRATION";  // calibration_t, in-situ identification
inline constexpr std::string_view kCellDiagnosis = "CELL_DIAGNOSIS";  // diagnosis_t, discrepancy on the cell's states
inline constexpr std::string_view kSimFault = "SIM_FAULT";  // sim_fault_t, fake hardware only
// The fake world's true sheet (sheet_state_t, SOURCE_OBSERVED with coverage 1), fake hardware only:
// lets tests and the monitor compare the tracker and the twin with the truth.
inline constexpr std::string_view kSimTruth = "SIM_SHEET_TRUTH";
// The fake world's simulation clock (sim_clock_t) and its lockstep clients' holds
// (sim_clock_hold_t), fake hardware only: drivers/sim_time.h.
inline constexpr std::string_view kSimClock = "SIM_CLOCK";
inline constexpr std::string_view kSimClockHold = "SIM_CLOCK_HOLD";

// Arm names of the standard cell.
inline constexpr std::string_view kArmLeft = "LEFT";      // iiwa 7 R800
inline constexpr std::string_view kArmRight = "RIGHT";    // iiwa 7 R800
inline constexpr std::string_view kArmCenter = "CENTER";  // iiwa 14 R820

// PREFIX + device name upper-cased. Throws std::invalid_argument naming the device if it is
// empty or has characters other than letters, digits and '_' (configuration-time use only).
std::string device_channel(std::string_view prefix, std::string_view device);

inline std::string iiwa_command(std::string_view arm) {
  return device_channel(kIiwaCommandPrefix, arm);
}
inline std::string iiwa_status(std::string_view arm) {
  return device_channel(kIiwaStatusPrefix, arm);
}
inline std::string gripper_command(std::string_view arm) {
  return device_channel(kGripperCommandPrefix, arm);
}
inline std::string gripper_status(std::string_view arm) {
  return device_channel(kGripperStatusPrefix, arm);
}
inline std::string camera_status(std::string_view camera) {
  return device_channel(kCameraStatusPrefix, camera);
}

}  // namespace drivers::channels
