#include "cell/log_settled_states.h"

#include <lcm/lcm-cpp.hpp>
#include <lcmt_iiwa_status.hpp>
#include <map>
#include <optional>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <stdexcept>

#include "drivers/lcm_channels.h"
#include "drivers/lcm_message_checks.h"
#include "drivers/lcm_wire_check.h"

namespace cell {
namespace {

namespace ch = drivers::channels;

template <typename T>
bool decode(const lcm::LogEvent& e, T& msg) {
  return drivers::decode_checked(e.data, static_cast<int>(e.datalen), msg).empty() &&
         drivers::message_problem(msg).empty();
}

bool starts_with(const std::string& s, std::string_view prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

std::vector<twin::Vec3> points(const prepreg_lcm::sheet_state_t& m) {
  std::vector<twin::Vec3> out;
  for (int v = 0; v < m.num_vertices; ++v) out.emplace_back(m.x_m[v], m.y_m[v], m.z_m[v]);
  return out;
}

}  // namespace

LoggedStates settled_states_from_log(const std::string& log_path, const CellConfig& config,
                                     const twin::GraspPlan& plan) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("LCM log " + log_path + ": cannot open for reading");
  const int vertex_count = config.sheet.mesh.vertex_count();
  const int grasps = static_cast<int>(plan.grasps.size());
  learning::SettledStateDetector detector(vertex_count, grasps, config.cell.cycle_hz, config.learning.settle);
  learning::SettledStateStore store(config.learning.max_states);
  std::map<std::string, drivers::JointVector> joints;  // by arm name
  std::map<std::string, bool> holding;                 // by gripper name
  std::vector<twin::Vec3> truth;
  std::optional<std::int64_t> first_utime;
  std::int64_t events = 0;
  LoggedStates out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    ++events;
    const std::string& channel = e->channel;
    if (starts_with(channel, ch::kIiwaStatusPrefix)) {
      lcmt_iiwa_status m;
      if (!decode(*e, m) || m.num_joints != 7) {
        ++out.undecodable;
        continue;
      }
      ++out.arm_statuses;
      joints[channel.substr(ch::kIiwaStatusPrefix.size())] =
          Eigen::Map<const drivers::JointVector>(m.joint_position_measured.data());
    } else if (starts_with(channel, ch::kGripperStatusPrefix)) {
      prepreg_lcm::gripper_status_t m;
      if (!decode(*e, m)) {
        ++out.undecodable;
        continue;
      }
      ++out.gripper_statuses;
      holding[channel.substr(ch::kGripperStatusPrefix.size())] = m.holding;
    } else if (channel == ch::kSimTruth) {
      prepreg_lcm::sheet_state_t m;
      if (!decode(*e, m)) {
        ++out.undecodable;
        continue;
      }
      ++out.truths;
      truth = points(m);
    } else if (channel == ch::kSheetObserved) {
      prepreg_lcm::sheet_state_t m;
      if (!decode(*e, m)) {
        ++out.undecodable;
        continue;
      }
      ++out.observed_sheets;
      if (m.num_vertices != vertex_count || m.num_observed_flags != vertex_count) {
        ++out.other_mesh;
        continue;
      }
      if (!first_utime) first_utime = e->timestamp;
      std::vector<twin::Vec3> grasp_positions;
      std::vector<char> engaged;
      for (const twin::Grasp& g : plan.grasps) {
        twin::Vec3 at = g.hold_position_m;
        const drivers::GripperConfig* gripper = config.hardware.find_gripper(g.gripper);
        const drivers::ArmConfig* arm = gripper && !gripper->arm.empty() ? config.hardware.find_arm(gripper->arm) : nullptr;
        if (arm) {
          const auto q = joints.find(arm->name);
          if (q != joints.end()) at = drivers::jaw_position(*arm, arm->arm().flange_in_cell(q->second));
        }
        grasp_positions.push_back(at);
        const auto h = holding.find(g.gripper);
        engaged.push_back(h == holding.end() || h->second ? 1 : 0);
      }
      const std::vector<std::uint8_t> seen(m.vertex_observed.begin(), m.vertex_observed.end());
      auto state = detector.add_cycle(1e-6 * static_cast<double>(e->timestamp - *first_utime), m.cycle_id,
                                      grasp_positions, engaged, points(m), seen);
      if (state) {
        state->truth_m = truth;
        store.add(std::move(*state));
      }
    }
  }
  if (events == 0) throw std::runtime_error("LCM log " + log_path + ": no events (empty or not an LCM log)");
  out.states = store.states();
  return out;
}

}  // namespace cell
