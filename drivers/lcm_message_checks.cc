#include "drivers/lcm_message_checks.h"

#include <utility>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <set>
#include <string_view>
#include <vector>

namespace drivers {
namespace {

// "" if `values` has `count` elements (count in [0, max]), else the problem.
template <typename V>
std::string count_problem(std::string_view field, const std::vector<V>& values, long long count,
                          long long max) {
  if (count < 0 || count > max) {
    return std::string(field) + ": count " + std::to_string(count) + " outside [0, " +
           std::to_string(max) + "]";
  }
  if (static_cast<long long>(values.size()) != count) {
    return std::string(field) + ": " + std::to_string(values.size()) + " values for count " +
           std::to_string(count);
  }
  return {};
}

template <typename V>
std::string finite_problem(std::string_view field, const std::vector<V>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      return std::string(field) + "[" + std::to_string(i) + "] is not finite";
    }
  }
  return {};
}

std::string nonnegative_problem(std::string_view field, double value) {
  if (!std::isfinite(value) || value < 0) {
    return std::string(field) + " = " + std::to_string(value) + ", expected finite and >= 0";
  }
  return {};
}

std::string state_problem(std::string_view field, int value, int lowest, int highest) {
  if (value < lowest || value > highest) {
    return std::string(field) + " = " + std::to_string(value) + ", expected " +
           std::to_string(lowest) + ".." + std::to_string(highest);
  }
  return {};
}

// Returns the first non-empty problem.
template <typename... S>
std::string first(S&&... problems) {
  std::string result;
  ((result.empty() && !problems.empty() ? (result = std::move(problems), 0) : 0), ...);
  return result;
}

// Fitted parameters with 95 % intervals (calibration_t, diagnosis_t): counts match, values
// finite, each inside its own interval.
constexpr int kMaxEstimates = 32;
std::string estimates_problem(int count, const std::vector<std::string>& names, const std::vector<double>& values,
                              const std::vector<double>& lower95, const std::vector<double>& upper95) {
  std::string problem = first(count_problem("parameter_names", names, count, kMaxEstimates),
                              count_problem("values", values, count, kMaxEstimates),
                              count_problem("lower95", lower95, count, kMaxEstimates),
                              count_problem("upper95", upper95, count, kMaxEstimates), finite_problem("values", values),
                              finite_problem("lower95", lower95), finite_problem("upper95", upper95));
  if (!problem.empty()) return problem;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(lower95[i] <= values[i] && values[i] <= upper95[i])) {
      return "values[" + std::to_string(i) + "] = " + std::to_string(values[i]) + " outside its interval [" +
             std::to_string(lower95[i]) + ", " + std::to_string(upper95[i]) + "]";
    }
  }
  return "";
}

// Errors in m: each >= 0, or NaN where it was not measured.
std::string errors_problem(std::initializer_list<std::pair<const char*, double>> errors) {
  for (const auto& [field, value] : errors) {
    if (std::isinf(value) || value < 0) return std::string(field) + " = " + std::to_string(value) + ", expected >= 0 or NaN";
  }
  return "";
}

// Times (us since the epoch): from 0 to 2^53 us (the year 2255), so that any two can be
// subtracted (found by fuzzing: a monitor's latency overflowed on a utime near -2^63).
constexpr std::int64_t kMaxUtime = std::int64_t{1} << 53;
std::string times_problem(std::initializer_list<std::pair<const char*, std::int64_t>> times) {
  for (const auto& [field, value] : times) {
    if (value < 0 || value > kMaxUtime) {
      return std::string(field) + " = " + std::to_string(value) + ", expected 0.." + std::to_string(kMaxUtime) + " us";
    }
  }
  return "";
}

}  // namespace

std::string message_problem(const prepreg_lcm::sheet_state_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  using T = prepreg_lcm::sheet_state_t;
  const int n = msg.num_vertices;
  std::string problem = first(
      (msg.source == T::SOURCE_OBSERVED || msg.source == T::SOURCE_PREDICTED)
          ? std::string()
          : "source = " + std::to_string(msg.source) + ", expected 1 (observed) or 2 (predicted)",
      count_problem("x_m", msg.x_m, n, kMaxSheetVertices),
      count_problem("y_m", msg.y_m, n, kMaxSheetVertices),
      count_problem("z_m", msg.z_m, n, kMaxSheetVertices),
      (msg.num_observed_flags == 0 || msg.num_observed_flags == n)
          ? std::string()
          : "num_observed_flags = " + std::to_string(msg.num_observed_flags) +
                ", expected 0 or num_vertices = " + std::to_string(n),
      count_problem("vertex_observed", msg.vertex_observed, msg.num_observed_flags,
                    kMaxSheetVertices),
      (std::isfinite(msg.coverage) && msg.coverage >= 0 && msg.coverage <= 1)
          ? std::string()
          : "coverage = " + std::to_string(msg.coverage) + ", expected 0..1");
  if (!problem.empty()) return problem;
  // Positions must be finite where the vertex counts as seen (every vertex without flags).
  for (int i = 0; i < n; ++i) {
    const bool seen = msg.num_observed_flags == 0 || msg.vertex_observed[i];
    if (seen && !(std::isfinite(msg.x_m[i]) && std::isfinite(msg.y_m[i]) &&
                  std::isfinite(msg.z_m[i]))) {
      return "vertex " + std::to_string(i) + ": position is not finite";
    }
  }
  return {};
}

std::string message_problem(const prepreg_lcm::prediction_error_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}, {"frames_utime", msg.frames_utime}, {"prediction_utime", msg.prediction_utime}}); !time.empty()) return time;
  std::string problem = first(
      msg.num_compared < 0 ? "num_compared = " + std::to_string(msg.num_compared) + " < 0"
                           : std::string(),
      nonnegative_problem("mean_m", msg.mean_m), nonnegative_problem("max_m", msg.max_m),
      nonnegative_problem("score_m", msg.score_m),
      count_problem("vertex_error_m", msg.vertex_error_m, msg.num_vertex_errors,
                    kMaxSheetVertices));
  if (!problem.empty()) return problem;
  if (msg.mean_m > msg.max_m * (1 + 1e-6f)) {
    return "mean_m = " + std::to_string(msg.mean_m) + " exceeds max_m = " +
           std::to_string(msg.max_m);
  }
  // score = mean + 0.5 max, to float precision.
  const double expected = double(msg.mean_m) + 0.5 * double(msg.max_m);
  if (std::abs(msg.score_m - expected) > 1e-6 + 1e-5 * expected) {
    return "score_m = " + std::to_string(msg.score_m) + ", expected mean_m + 0.5 max_m = " +
           std::to_string(expected);
  }
  for (std::size_t i = 0; i < msg.vertex_error_m.size(); ++i) {
    const float e = msg.vertex_error_m[i];  // NaN marks an unobserved vertex
    if (std::isinf(e) || e < 0) {
      return "vertex_error_m[" + std::to_string(i) + "] = " + std::to_string(e) +
             ", expected >= 0 or NaN";
    }
  }
  return {};
}

std::string message_problem(const prepreg_lcm::camera_status_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}, {"last_frame_utime", msg.last_frame_utime}}); !time.empty()) return time;
  using T = prepreg_lcm::camera_status_t;
  return first(msg.name.empty() ? std::string("name is empty") : std::string(),
               state_problem("state", msg.state, T::STATE_UNCONFIGURED, T::STATE_LOST),
               msg.frames < 0 ? std::string("frames < 0") : std::string(),
               msg.dropped < 0 ? std::string("dropped < 0") : std::string(),
               msg.last_frame_utime < 0 ? std::string("last_frame_utime < 0") : std::string());
}

std::string message_problem(const prepreg_lcm::cell_state_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  using T = prepreg_lcm::cell_state_t;
  return first(
      state_problem("state", msg.state, T::STATE_STARTING, T::STATE_STOPPED),
      msg.cycle_id < -1 ? std::string("cycle_id < -1") : std::string(),
      msg.twin_reseeds < 0 ? "twin_reseeds = " + std::to_string(msg.twin_reseeds) + " < 0" : std::string(),
      (msg.num_cameras < 0 || msg.num_cameras_ok < 0 || msg.num_cameras_ok > msg.num_cameras)
          ? "num_cameras_ok = " + std::to_string(msg.num_cameras_ok) + ", num_cameras = " +
                std::to_string(msg.num_cameras) + ", expected 0 <= ok <= cameras"
          : std::string());
}

std::string message_problem(const prepreg_lcm::grasp_plan_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  const int n = msg.num_grasps;
  std::string problem = first(
      count_problem("material_u_m", msg.material_u_m, n, kMaxGrasps),
      count_problem("material_v_m", msg.material_v_m, n, kMaxGrasps),
      count_problem("cell_x_m", msg.cell_x_m, n, kMaxGrasps),
      count_problem("cell_y_m", msg.cell_y_m, n, kMaxGrasps),
      count_problem("cell_z_m", msg.cell_z_m, n, kMaxGrasps),
      count_problem("arm", msg.arm, n, kMaxGrasps),
      finite_problem("material_u_m", msg.material_u_m),
      finite_problem("material_v_m", msg.material_v_m),
      finite_problem("cell_x_m", msg.cell_x_m), finite_problem("cell_y_m", msg.cell_y_m),
      finite_problem("cell_z_m", msg.cell_z_m),
      nonnegative_problem("predicted_sag_m", msg.predicted_sag_m));
  if (!problem.empty()) return problem;
  for (int i = 0; i < n; ++i) {
    if (msg.arm[i].empty()) return "arm[" + std::to_string(i) + "] is empty";
  }
  return {};
}

std::string message_problem(const prepreg_lcm::gripper_command_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  using T = prepreg_lcm::gripper_command_t;
  return first(state_problem("action", msg.action, T::ACTION_OPEN, T::ACTION_CLOSE),
               nonnegative_problem("width_m", msg.width_m),
               nonnegative_problem("force_n", msg.force_n));
}

std::string message_problem(const prepreg_lcm::gripper_status_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  using T = prepreg_lcm::gripper_status_t;
  return first(state_problem("state", msg.state, T::STATE_OPEN, T::STATE_FAULT),
               nonnegative_problem("width_m", msg.width_m));
}

std::string message_problem(const prepreg_lcm::sim_fault_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  if (msg.target.empty()) return "target is empty";
  static const char* const kFaults[] = {"dead", "frozen", "stale", "drop", "bumped", "status_silent", "diverge", "slow"};
  for (const char* f : kFaults) {
    if (msg.fault == f) return "";
  }
  return "fault '" + msg.fault + "' is not one of dead, frozen, stale, drop, bumped, status_silent, diverge, slow";
}

std::string message_problem(const prepreg_lcm::sim_clock_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}, {"sim_us", msg.sim_us}}); !time.empty()) return time;
  using T = prepreg_lcm::sim_clock_t;
  if (!std::isfinite(msg.real_time_factor) || msg.real_time_factor < 0) {
    return "real_time_factor = " + std::to_string(msg.real_time_factor) + ", expected a finite number >= 0";
  }
  return state_problem("state", msg.state, T::STATE_RUNNING, T::STATE_HELD);
}

std::string message_problem(const prepreg_lcm::sim_clock_hold_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}, {"until_utime", msg.until_utime}}); !time.empty()) {
    return time;
  }
  if (msg.client.empty()) return "client is empty";
  return "";
}

std::string message_problem(const prepreg_lcm::calibration_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  if (msg.verdict != "adopted" && msg.verdict != "refused" && msg.verdict != "failed") {
    return "verdict '" + msg.verdict + "' is not one of adopted, refused, failed";
  }
  std::string problem =
      first(estimates_problem(msg.num_parameters, msg.parameter_names, msg.values, msg.lower95, msg.upper95),
            count_problem("determined", msg.determined, msg.num_parameters, kMaxEstimates),
            errors_problem({{"held_out_error_before_m", msg.held_out_error_before_m},
                            {"held_out_error_after_m", msg.held_out_error_after_m},
                            {"fitted_rms_before_m", msg.fitted_rms_before_m},
                            {"fitted_rms_after_m", msg.fitted_rms_after_m}}));
  if (!problem.empty()) return problem;
  return first(msg.states_fitted < 0 ? "states_fitted < 0" : std::string(),
               msg.states_held_out < 0 ? "states_held_out < 0" : std::string(),
               msg.simulations < 0 ? "simulations < 0" : std::string(), nonnegative_problem("seconds", msg.seconds));
}

std::string message_problem(const prepreg_lcm::diagnosis_t& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  static const std::set<std::string> kVerdicts = {"effect", "none", "unexplained", "model_form", "failed"};
  static const std::set<std::string> kAdoptions = {"adopted", "not named", "refused", "failed"};
  if (!kVerdicts.count(msg.verdict)) {
    return "verdict '" + msg.verdict + "' is not one of effect, none, unexplained, model_form, failed";
  }
  if (!kAdoptions.count(msg.adoption)) {
    return "adoption '" + msg.adoption + "' is not one of adopted, not named, refused, failed";
  }
  if (msg.adoption == "adopted" && msg.verdict != "effect") return "adoption 'adopted' without verdict 'effect'";
  std::string problem =
      first(estimates_problem(msg.num_parameters, msg.parameter_names, msg.values, msg.lower95, msg.upper95),
            errors_problem({{"noise_sigma_m", msg.noise_sigma_m},
                            {"base_fitted_mean_m", msg.base_fitted_mean_m},
                            {"base_held_out_mean_m", msg.base_held_out_mean_m},
                            {"effect_fitted_mean_m", msg.effect_fitted_mean_m},
                            {"effect_held_out_mean_m", msg.effect_held_out_mean_m},
                            {"held_out_error_before_m", msg.held_out_error_before_m},
                            {"held_out_error_after_m", msg.held_out_error_after_m}}));
  if (!problem.empty()) return problem;
  return first(msg.states < 0 ? "states < 0" : std::string(), nonnegative_problem("seconds", msg.seconds));
}

std::string message_problem(const lcmt_iiwa_command& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  return first(count_problem("joint_position", msg.joint_position, msg.num_joints, kMaxIiwaJoints),
               count_problem("joint_torque", msg.joint_torque, msg.num_torques, kMaxIiwaJoints),
               finite_problem("joint_position", msg.joint_position),
               finite_problem("joint_torque", msg.joint_torque));
}

std::string message_problem(const lcmt_iiwa_status& msg) {
  if (std::string time = times_problem({{"utime", msg.utime}}); !time.empty()) return time;
  const int n = msg.num_joints;
  return first(
      count_problem("joint_position_measured", msg.joint_position_measured, n, kMaxIiwaJoints),
      count_problem("joint_velocity_estimated", msg.joint_velocity_estimated, n, kMaxIiwaJoints),
      count_problem("joint_position_commanded", msg.joint_position_commanded, n, kMaxIiwaJoints),
      count_problem("joint_position_ipo", msg.joint_position_ipo, n, kMaxIiwaJoints),
      count_problem("joint_torque_measured", msg.joint_torque_measured, n, kMaxIiwaJoints),
      count_problem("joint_torque_commanded", msg.joint_torque_commanded, n, kMaxIiwaJoints),
      count_problem("joint_torque_external", msg.joint_torque_external, n, kMaxIiwaJoints),
      finite_problem("joint_position_measured", msg.joint_position_measured),
      finite_problem("joint_velocity_estimated", msg.joint_velocity_estimated),
      finite_problem("joint_position_commanded", msg.joint_position_commanded));
}

}  // namespace drivers
