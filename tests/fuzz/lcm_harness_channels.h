#pragma once
// The channels each LCM harness publishes on, in the order the first byte of a message record
// picks them (lcm_fuzz_support.h). Shared with make_lcm_seeds so that seeds land on the channel
// they were made for.

#include <string>
#include <vector>

#include "drivers/cell_hardware_config.h"
#include "drivers/lcm_channels.h"

namespace fuzz {

// cell_monitor subscribes to all of these (CAMERA_STATUS_.*, IIWA_STATUS_.*, ... by pattern).
inline std::vector<std::string> monitor_channels() {
  namespace ch = drivers::channels;
  return {std::string(ch::kCellState),     std::string(ch::kCellCalibration),
          std::string(ch::kCellDiagnosis), std::string(ch::kPredictionError),
          std::string(ch::kSheetObserved), std::string(ch::kSheetPredicted),
          std::string(ch::kSimTruth),      ch::camera_status("cam_left"),
          ch::iiwa_status("LEFT"),         ch::gripper_status("LEFT"),
          ch::camera_status("cam_right"),  ch::iiwa_status("CENTER")};
}

// The cell controller's and its robot link's subscriptions for `hardware`.
inline std::vector<std::string> cell_channels(const drivers::CellHardwareConfig& hardware) {
  namespace ch = drivers::channels;
  std::vector<std::string> c = {std::string(ch::kSimTruth), std::string(ch::kSimFault)};
  for (const auto& arm : hardware.arms) c.push_back(ch::iiwa_status(arm.name));
  for (const auto& g : hardware.grippers) c.push_back(ch::gripper_status(g.name));
  c.push_back(std::string(ch::kSimClock));  // the fake cell runs on the world's clock
  return c;
}

// The fake world's subscriptions for `hardware` (every arm and every gripper an arm holds).
inline std::vector<std::string> world_channels(const drivers::CellHardwareConfig& hardware) {
  namespace ch = drivers::channels;
  std::vector<std::string> c = {std::string(ch::kSimFault)};
  for (const auto& arm : hardware.arms) c.push_back(ch::iiwa_command(arm.name));
  for (const auto& g : hardware.grippers) c.push_back(ch::gripper_command(g.name));
  c.push_back(std::string(ch::kSimClockHold));  // its lockstep client's holds
  return c;
}

}  // namespace fuzz
