#include "drivers/cell_hardware_config.h"

#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

#include "drivers/json_field.h"
#include "drivers/pose_json.h"

namespace drivers {
namespace {

bool valid_device_name(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    if (!ok) return false;
  }
  return true;
}

std::string read_name(const JsonField& f) {
  const std::string name = f.string();
  if (!valid_device_name(name)) f.fail("must be letters, digits and '_' (it names LCM channels), got '" + name + "'");
  return name;
}

ArmConfig read_arm(const JsonField& f) {
  f.only_keys({"name", "model", "base_in_cell", "tool_length_m", "home_deg"});
  ArmConfig arm;
  arm.name = read_name(f["name"]);
  const std::string model = f["model"].string();
  try {
    arm.model = iiwa_model_from_string(model);
  } catch (const std::invalid_argument&) {
    f["model"].fail("must be \"iiwa7\" (LBR iiwa 7 R800) or \"iiwa14\" (LBR iiwa 14 R820), got '" + model + "'");
  }
  arm.base_in_cell = parse_pose(f["base_in_cell"]);
  if (f.has("tool_length_m")) {
    const double length = f["tool_length_m"].number();
    if (length < 0 || length > 1.0) f["tool_length_m"].fail("must be within 0 .. 1 m");
    arm.tool_length_m = length;
  }
  if (f.has("home_deg")) {
    const std::vector<double> deg = f["home_deg"].numbers(kIiwaJoints);
    for (int j = 0; j < kIiwaJoints; ++j) arm.home_rad[j] = deg[j] * M_PI / 180.0;
    if (!arm.arm().within_limits(arm.home_rad)) f["home_deg"].fail("is outside the arm's joint limits");
  }
  return arm;
}

}  // namespace

const ArmConfig* CellHardwareConfig::find_arm(const std::string& name) const {
  for (const ArmConfig& a : arms) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

const GripperConfig* CellHardwareConfig::find_gripper(const std::string& name) const {
  for (const GripperConfig& g : grippers) {
    if (g.name == name) return &g;
  }
  return nullptr;
}

CellHardwareConfig parse_cell_hardware(const nlohmann::json& document, const std::string& source) {
  const JsonField root(document, source);
  CellHardwareConfig config;
  if (root.has("arms")) {
    const JsonField arms = root["arms"];
    std::set<std::string> names;
    for (std::size_t i = 0; i < arms.size(); ++i) {
      ArmConfig arm = read_arm(arms.at(i));
      if (!names.insert(arm.name).second) arms.at(i)["name"].fail("repeats arm '" + arm.name + "'");
      config.arms.push_back(arm);
    }
  }
  if (root.has("grippers")) {
    const JsonField grippers = root["grippers"];
    std::set<std::string> names, used_arms;
    for (std::size_t i = 0; i < grippers.size(); ++i) {
      const JsonField g = grippers.at(i);
      g.only_keys({"name", "arm"});
      GripperConfig gripper;
      gripper.name = read_name(g["name"]);
      if (!names.insert(gripper.name).second) g["name"].fail("repeats gripper '" + gripper.name + "'");
      if (g.has("arm")) {
        gripper.arm = g["arm"].string();
        if (!config.find_arm(gripper.arm)) g["arm"].fail("names no arm of this file ('" + gripper.arm + "')");
        if (!used_arms.insert(gripper.arm).second) g["arm"].fail("already carries a gripper ('" + gripper.arm + "')");
      }
      config.grippers.push_back(gripper);
    }
  }
  return config;
}

CellHardwareConfig read_cell_hardware(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the cell config");
  const nlohmann::json document = parse_json_stream(in, path);
  return parse_cell_hardware(document, path);
}

Eigen::Isometry3d flange_pose_for_jaw(const ArmConfig& arm, const Eigen::Vector3d& jaw, double yaw_rad) {
  Eigen::Isometry3d flange = Eigen::Isometry3d::Identity();
  // Rx(pi): z down; then the yaw about the cell's vertical.
  flange.linear() = (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())).toRotationMatrix();
  flange.translation() = jaw - flange.linear() * Eigen::Vector3d(0, 0, arm.tool_length_m);
  return flange;
}

Eigen::Vector3d jaw_position(const ArmConfig& arm, const Eigen::Isometry3d& flange_in_cell) {
  return flange_in_cell * Eigen::Vector3d(0, 0, arm.tool_length_m);
}

}  // namespace drivers
