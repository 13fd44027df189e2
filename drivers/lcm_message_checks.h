#pragma once
// Checks of the cell's LCM messages before they are acted on (received) or encoded (published).
// LCM's generated decoder only checks the fingerprint and the length; these check what the
// decoder cannot: enum values in range, array lengths consistent with their counts (an encoder
// would read past a vector that is shorter than its count), finite numbers, values in their
// physical range. Each returns "" when the message is acceptable, otherwise what is wrong.
// They never throw.

#include <string>

#include <lcmt_iiwa_command.hpp>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/calibration_t.hpp>
#include <prepreg_lcm/diagnosis_t.hpp>
#include <prepreg_lcm/camera_status_t.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/grasp_plan_t.hpp>
#include <prepreg_lcm/gripper_command_t.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>
#include <prepreg_lcm/sim_fault_t.hpp>

namespace drivers {

// Largest counts accepted (far above the cell's needs; guards against absurd allocations).
inline constexpr int kMaxSheetVertices = 1'000'000;
inline constexpr int kMaxGrasps = 16;
inline constexpr int kMaxIiwaJoints = 7;

std::string message_problem(const prepreg_lcm::sheet_state_t& msg);
std::string message_problem(const prepreg_lcm::prediction_error_t& msg);
std::string message_problem(const prepreg_lcm::camera_status_t& msg);
std::string message_problem(const prepreg_lcm::cell_state_t& msg);
std::string message_problem(const prepreg_lcm::grasp_plan_t& msg);
std::string message_problem(const prepreg_lcm::gripper_command_t& msg);
std::string message_problem(const prepreg_lcm::gripper_status_t& msg);
std::string message_problem(const prepreg_lcm::sim_fault_t& msg);
std::string message_problem(const prepreg_lcm::sim_clock_t& msg);
std::string message_problem(const prepreg_lcm::sim_clock_hold_t& msg);
// Verdict one of adopted / refused / failed; parameter arrays of the count with finite values
// and lower95 <= value <= upper95; errors >= 0 or NaN (a simulation that failed).
std::string message_problem(const prepreg_lcm::calibration_t& msg);
std::string message_problem(const prepreg_lcm::diagnosis_t& msg);
// iiwa: 0..7 joints (a real arm sends 7; 0 is a valid empty torque-mode position list).
std::string message_problem(const lcmt_iiwa_command& msg);
std::string message_problem(const lcmt_iiwa_status& msg);

}  // namespace drivers
