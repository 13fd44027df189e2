#include "drivers/lcm_wire_check.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace drivers {
namespace {

// One field of a layout: a scalar, or an array whose count is an earlier integer field.
struct WireField {
  std::string name;
  int bytes = 0;       // per element; 0 for a string (int32 length, then that many bytes)
  bool integer = false;
  int count_of = -1;   // index of the count field, -1 for a scalar
};

// Layouts in the order of the .lcm files' fields: "type name" per field, "type name[count]"
// for an array (count: an earlier integer field). Types: int8_t int16_t int32_t int64_t float
// double boolean byte string.
const std::map<std::string, std::string, std::less<>>& layout_texts() {
  static const std::map<std::string, std::string, std::less<>> texts = {
      {"sheet_state_t",
       "int64_t utime; int64_t cycle_id; int8_t source; int32_t num_vertices; float x_m[num_vertices]; "
       "float y_m[num_vertices]; float z_m[num_vertices]; int32_t num_observed_flags; "
       "boolean vertex_observed[num_observed_flags]; float coverage"},
      {"prediction_error_t",
       "int64_t utime; int64_t cycle_id; int64_t frames_utime; int64_t prediction_utime; int32_t num_compared; "
       "float mean_m; float max_m; float score_m; int32_t num_vertex_errors; float vertex_error_m[num_vertex_errors]"},
      {"cell_state_t",
       "int64_t utime; int64_t cycle_id; int8_t state; string reason; boolean cameras_ok; boolean tracker_ok; "
       "boolean twin_ok; boolean robots_ok; boolean grippers_ok; int8_t num_cameras_ok; int8_t num_cameras; "
       "int32_t twin_reseeds"},
      {"camera_status_t",
       "int64_t utime; string name; int8_t state; int64_t frames; int64_t dropped; boolean stale; boolean frozen; "
       "int64_t last_frame_utime; string message"},
      {"gripper_status_t", "int64_t utime; int8_t state; float width_m; boolean holding"},
      {"gripper_command_t", "int64_t utime; int8_t action; float width_m; float force_n"},
      {"sim_fault_t", "int64_t utime; string target; string fault; boolean active"},
      {"sim_clock_t", "int64_t utime; int64_t sim_us; double real_time_factor; int8_t state; string held_by"},
      {"sim_clock_hold_t", "int64_t utime; string client; int64_t until_utime; boolean leaving"},
      {"grasp_plan_t",
       "int64_t utime; int64_t plan_id; int32_t num_grasps; float material_u_m[num_grasps]; "
       "float material_v_m[num_grasps]; float cell_x_m[num_grasps]; float cell_y_m[num_grasps]; "
       "float cell_z_m[num_grasps]; string arm[num_grasps]; float predicted_sag_m; boolean feasible; string note"},
      {"calibration_t",
       "int64_t utime; int64_t calibration_id; string verdict; string reason; int32_t num_parameters; "
       "string parameter_names[num_parameters]; double values[num_parameters]; double lower95[num_parameters]; "
       "double upper95[num_parameters]; boolean determined[num_parameters]; double held_out_error_before_m; "
       "double held_out_error_after_m; double fitted_rms_before_m; double fitted_rms_after_m; "
       "int32_t states_fitted; int32_t states_held_out; int32_t simulations; double seconds; string material_file"},
      {"diagnosis_t",
       "int64_t utime; int64_t diagnosis_id; string verdict; string effect; string adoption; string reason; "
       "double noise_sigma_m; double base_fitted_mean_m; double base_held_out_mean_m; double effect_fitted_mean_m; "
       "double effect_held_out_mean_m; int32_t num_parameters; string parameter_names[num_parameters]; "
       "double values[num_parameters]; double lower95[num_parameters]; double upper95[num_parameters]; "
       "double held_out_error_before_m; double held_out_error_after_m; int32_t states; double seconds; "
       "string report_directory; string material_file"},
      {"lcmt_iiwa_command",
       "int64_t utime; int32_t num_joints; double joint_position[num_joints]; int32_t num_torques; "
       "double joint_torque[num_torques]"},
      {"lcmt_iiwa_status",
       "int64_t utime; int32_t num_joints; double joint_position_measured[num_joints]; "
       "double joint_velocity_estimated[num_joints]; double joint_position_commanded[num_joints]; "
       "double joint_position_ipo[num_joints]; double joint_torque_measured[num_joints]; "
       "double joint_torque_commanded[num_joints]; double joint_torque_external[num_joints]"},
  };
  return texts;
}

std::vector<WireField> parse_layout(const std::string& type, const std::string& text) {
  static const std::map<std::string, std::pair<int, bool>> kinds = {
      {"int8_t", {1, true}}, {"int16_t", {2, true}}, {"int32_t", {4, true}}, {"int64_t", {8, true}},
      {"float", {4, false}}, {"double", {8, false}}, {"boolean", {1, false}}, {"byte", {1, false}},
      {"string", {0, false}}};
  std::vector<WireField> fields;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ';');) {
    std::istringstream words(item);
    std::string kind, name;
    words >> kind >> name;
    const auto k = kinds.find(kind);
    if (k == kinds.end() || name.empty()) throw std::logic_error("lcm wire layout of " + type + ": bad field '" + item + "'");
    WireField f{name, k->second.first, k->second.second, -1};
    if (const auto open = name.find('['); open != std::string::npos) {
      const std::string count = name.substr(open + 1, name.size() - open - 2);
      f.name = name.substr(0, open);
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].name == count && fields[i].integer && fields[i].count_of < 0) f.count_of = static_cast<int>(i);
      }
      if (f.count_of < 0) throw std::logic_error("lcm wire layout of " + type + ": no count field '" + count + "'");
    }
    fields.push_back(f);
  }
  return fields;
}

const std::vector<WireField>* layout_of(std::string_view type_name) {
  static const std::map<std::string, std::vector<WireField>, std::less<>> layouts = [] {
    std::map<std::string, std::vector<WireField>, std::less<>> out;
    for (const auto& [type, text] : layout_texts()) out[type] = parse_layout(type, text);
    return out;
  }();
  // getTypeName() is the bare struct name for our package's types (LCM's own convention).
  const auto it = layouts.find(type_name);
  return it == layouts.end() ? nullptr : &it->second;
}

std::int64_t read_big_endian(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  // Sign-extend from `bytes` bytes.
  if (bytes < 8 && (v >> (8 * bytes - 1)) & 1) v |= ~std::uint64_t{0} << (8 * bytes);
  return static_cast<std::int64_t>(v);
}

}  // namespace

bool has_wire_layout(std::string_view type_name) { return layout_of(type_name) != nullptr; }

std::string wire_problem(std::string_view type_name, const void* data, int size) {
  const std::vector<WireField>* layout = layout_of(type_name);
  if (layout == nullptr) throw std::logic_error("no LCM wire layout for type " + std::string(type_name));
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  if (size < 8) return std::to_string(size) + " bytes: shorter than the fingerprint";
  std::int64_t pos = 8;
  std::vector<std::int64_t> values(layout->size(), 0);
  auto left = [&] { return static_cast<std::int64_t>(size) - pos; };
  for (std::size_t i = 0; i < layout->size(); ++i) {
    const WireField& f = (*layout)[i];
    // A negative count: lcm-gen's decode would throw std::length_error resizing to it.
    if (f.count_of >= 0 && values[f.count_of] < 0) {
      return (*layout)[f.count_of].name + " " + std::to_string(values[f.count_of]) + " is negative";
    }
    const std::int64_t n = f.count_of < 0 ? 1 : values[f.count_of];
    if (f.bytes > 0) {
      if (n > left() / f.bytes) {
        return f.count_of < 0
                   ? "field " + f.name + " is cut off (" + std::to_string(left()) + " bytes left)"
                   : (*layout)[f.count_of].name + " " + std::to_string(n) + " needs " + std::to_string(n * f.bytes) +
                         " bytes for " + f.name + ", " + std::to_string(left()) + " left";
      }
      if (f.integer && f.count_of < 0) values[i] = read_big_endian(bytes + pos, f.bytes);
      pos += n * f.bytes;
      continue;
    }
    // Strings: int32 length (with the terminating NUL), then the characters.
    if (f.count_of >= 0 && n > left() / 4) {
      return (*layout)[f.count_of].name + " " + std::to_string(n) + " needs at least " + std::to_string(4 * n) +
             " bytes for " + f.name + ", " + std::to_string(left()) + " left";
    }
    for (std::int64_t e = 0; e < n; ++e) {
      if (left() < 4) return "string " + f.name + " is cut off";
      const std::int64_t length = read_big_endian(bytes + pos, 4);
      pos += 4;
      if (length < 1 || length > left()) {
        return "string " + f.name + " has length " + std::to_string(length) + ", " + std::to_string(left()) + " bytes left";
      }
      pos += length;
    }
  }
  if (pos != size) return std::to_string(size - pos) + " bytes after the last field of " + std::string(type_name);
  return "";
}

}  // namespace drivers
