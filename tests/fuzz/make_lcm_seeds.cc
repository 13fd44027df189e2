// Writes the seed corpora of the LCM harnesses (tests/fuzz/corpus/lcm_*/seed_*): message records
// (lcm_fuzz_support.h) of every type each harness's channels carry, with plausible contents, and a
// small lcm-logger log for lcm_log. Run from the fuzz build after a message type changes:
//   build-asan/tests/fuzz/make_lcm_seeds tests/fuzz/corpus
#include <lcm/lcm-cpp.hpp>
#include <lcmt_iiwa_command.hpp>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/calibration_t.hpp>
#include <prepreg_lcm/camera_status_t.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/diagnosis_t.hpp>
#include <prepreg_lcm/gripper_command_t.hpp>
#include <prepreg_lcm/gripper_status_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_clock_hold_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>
#include <prepreg_lcm/sim_fault_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cell/cell_config.h"
#include "drivers/iiwa_lcm.h"
#include "drivers/lcm_channels.h"
#include "tests/fuzz/lcm_harness_channels.h"

namespace fs = std::filesystem;
namespace ch = drivers::channels;

namespace {

constexpr std::int64_t kUtime = 1'700'000'000'000'000;

template <typename T>
std::string encode(const T& msg) {
  std::string bytes(static_cast<std::size_t>(msg.getEncodedSize()), '\0');
  if (msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())) != static_cast<int>(bytes.size())) {
    throw std::runtime_error(std::string("cannot encode ") + T::getTypeName());
  }
  return bytes;
}

// Records: channel index (in `channels`), length, payload.
class Records {
 public:
  explicit Records(std::vector<std::string> channels) : channels_(std::move(channels)) {}
  template <typename T>
  Records& add(const std::string& channel, const T& msg) {
    const auto it = std::find(channels_.begin(), channels_.end(), channel);
    if (it == channels_.end()) throw std::runtime_error("no channel " + channel);
    const std::string payload = encode(msg);
    if (payload.size() > 0xffff) throw std::runtime_error("message too long for a record: " + channel);
    bytes_ += static_cast<char>(it - channels_.begin());
    bytes_ += static_cast<char>(payload.size() & 0xff);
    bytes_ += static_cast<char>(payload.size() >> 8);
    bytes_ += payload;
    return *this;
  }
  void write(const fs::path& file) const {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << bytes_;
  }

 private:
  std::vector<std::string> channels_;
  std::string bytes_;
};

prepreg_lcm::sheet_state_t sheet(std::int64_t cycle, std::int8_t source, int n, bool flags) {
  prepreg_lcm::sheet_state_t s{};
  s.utime = kUtime + cycle * 33'333;
  s.cycle_id = cycle;
  s.source = source;
  s.num_vertices = n;
  for (int i = 0; i < n; ++i) {
    s.x_m.push_back(0.1f * static_cast<float>(i % 4));
    s.y_m.push_back(0.01f * static_cast<float>(i));
    s.z_m.push_back(1.0f - 0.1f * static_cast<float>(i / 4));
  }
  s.num_observed_flags = flags ? n : 0;
  if (flags) s.vertex_observed.assign(static_cast<std::size_t>(n), true);
  if (flags && n > 1) s.vertex_observed[1] = false;
  s.coverage = flags ? 0.9f : 1.0f;
  return s;
}

prepreg_lcm::prediction_error_t prediction_error(std::int64_t cycle, int n) {
  prepreg_lcm::prediction_error_t e{};
  e.utime = kUtime + cycle * 33'333;
  e.cycle_id = cycle;
  e.frames_utime = e.utime - 20'000;
  e.prediction_utime = e.utime - 10'000;
  e.num_compared = n - 1;
  e.mean_m = 0.01f;
  e.max_m = 0.03f;
  e.score_m = e.mean_m + 0.5f * e.max_m;
  e.num_vertex_errors = n;
  for (int i = 0; i < n; ++i) e.vertex_error_m.push_back(i == 1 ? NAN : 0.01f);
  return e;
}

prepreg_lcm::cell_state_t cell_state(std::int64_t cycle, std::int8_t state, const char* reason) {
  prepreg_lcm::cell_state_t s{};
  s.utime = kUtime + cycle * 33'333 + 1000;
  s.cycle_id = cycle;
  s.state = state;
  s.reason = reason;
  s.cameras_ok = s.tracker_ok = s.twin_ok = s.robots_ok = s.grippers_ok = true;
  s.num_cameras_ok = 3;
  s.num_cameras = 3;
  return s;
}

prepreg_lcm::camera_status_t camera(const std::string& name, std::int8_t state) {
  prepreg_lcm::camera_status_t c{};
  c.utime = kUtime;
  c.name = name;
  c.state = state;
  c.frames = 120;
  c.dropped = 2;
  c.last_frame_utime = kUtime - 30'000;
  c.message = state == prepreg_lcm::camera_status_t::STATE_ACTIVE ? "" : "cam lost: VIDIOC_DQBUF: No such device";
  return c;
}

prepreg_lcm::gripper_status_t gripper_status(bool holding) {
  prepreg_lcm::gripper_status_t g{};
  g.utime = kUtime;
  g.state = holding ? prepreg_lcm::gripper_status_t::STATE_CLOSED : prepreg_lcm::gripper_status_t::STATE_OPEN;
  g.width_m = holding ? 0.0f : 0.06f;
  g.holding = holding;
  return g;
}

prepreg_lcm::gripper_command_t gripper_command(std::int8_t action) {
  prepreg_lcm::gripper_command_t g{};
  g.utime = kUtime;
  g.action = action;
  g.width_m = 0.06f;
  g.force_n = 40.0f;
  return g;
}

prepreg_lcm::sim_fault_t fault(const char* target, const char* what, bool active) {
  prepreg_lcm::sim_fault_t f{};
  f.utime = kUtime;
  f.target = target;
  f.fault = what;
  f.active = active;
  return f;
}

drivers::JointVector joints(double offset) {
  drivers::JointVector q;
  for (int j = 0; j < 7; ++j) q[j] = offset + 0.1 * j;
  return q;
}

lcmt_iiwa_status arm_status(double offset) {
  const drivers::JointVector q = joints(offset);
  return drivers::make_iiwa_status(kUtime, q, drivers::JointVector::Zero(), q);
}

prepreg_lcm::calibration_t calibration() {
  prepreg_lcm::calibration_t c{};
  c.utime = kUtime;
  c.calibration_id = 1;
  c.verdict = "adopted";
  c.reason = "held-out state 12.7 -> 8.0 mm";
  c.num_parameters = 2;
  c.parameter_names = {"membrane_stiffness_N_m", "bending_rigidity_Nm"};
  c.values = {4000.0, 0.002};
  c.lower95 = {3500.0, 0.0015};
  c.upper95 = {4500.0, 0.0025};
  c.determined = {true, true};
  c.held_out_error_before_m = 0.0127;
  c.held_out_error_after_m = 0.008;
  c.fitted_rms_before_m = 0.0096;
  c.fitted_rms_after_m = 0.0035;
  c.states_fitted = 2;
  c.states_held_out = 1;
  c.simulations = 40;
  c.seconds = 102.0;
  c.material_file = "out/learning/calibration_1/material.json";
  return c;
}

prepreg_lcm::diagnosis_t diagnosis() {
  prepreg_lcm::diagnosis_t d{};
  d.utime = kUtime;
  d.verdict = "effect";
  d.effect = "clamp_grip";
  d.adoption = "adopted";
  d.noise_sigma_m = 0.0034;
  d.base_fitted_mean_m = 0.0086;
  d.base_held_out_mean_m = 0.0109;
  d.effect_fitted_mean_m = 0.0051;
  d.effect_held_out_mean_m = 0.0080;
  d.num_parameters = 2;
  d.parameter_names = {"clamp_grip_strength", "clamp_grip_width_m"};
  d.values = {0.0075, 0.012};
  d.lower95 = {0.0070, 0.011};
  d.upper95 = {0.0081, 0.013};
  d.held_out_error_before_m = 0.0127;
  d.held_out_error_after_m = 0.008;
  d.states = 3;
  d.seconds = 641.6;
  return d;
}

void write_log(const fs::path& file, const std::vector<std::pair<std::string, std::string>>& events) {
  fs::create_directories(file.parent_path());
  std::string path = file.string();
  // lcm_log_fuzz.cc takes one byte first: which tool reads the log.
  for (const char tool : {'\0', '\1', '\2'}) {
    const std::string log_path = path + "_tool" + std::to_string(static_cast<int>(tool));
    {
      lcm::LogFile log(log_path + ".tmp", "w");
      if (!log.good()) throw std::runtime_error("cannot write " + log_path);
      std::int64_t t = kUtime;
      std::int64_t n = 0;
      for (const auto& [channel, payload] : events) {
        lcm::LogEvent e{};
        e.eventnum = n++;
        e.timestamp = t += 10'000;
        e.channel = channel;
        e.datalen = static_cast<std::int32_t>(payload.size());
        e.data = const_cast<char*>(payload.data());
        log.writeEvent(&e);
      }
    }
    std::ifstream in(log_path + ".tmp", std::ios::binary);
    std::ofstream out(log_path, std::ios::binary);
    out << tool << in.rdbuf();
    fs::remove(log_path + ".tmp");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_lcm_seeds CORPUS_DIR (tests/fuzz/corpus)\n");
    return 2;
  }
  const fs::path corpus = argv[1];
  const cell::CellConfig config = cell::read_cell_config(PREPREG_SOURCE_DIR "/cell/examples/fake_cell.json");
  using S = prepreg_lcm::sheet_state_t;
  using C = prepreg_lcm::cell_state_t;
  using G = prepreg_lcm::gripper_command_t;
  using Cam = prepreg_lcm::camera_status_t;

  // The monitor: two cycles as the cell publishes them, a state change, statuses, learning.
  const auto m = fuzz::monitor_channels();
  Records cycles(m);
  for (std::int64_t cycle = 1; cycle <= 2; ++cycle) {
    cycles.add(std::string(ch::kSheetObserved), sheet(cycle, S::SOURCE_OBSERVED, 8, true))
        .add(std::string(ch::kSheetPredicted), sheet(cycle, S::SOURCE_PREDICTED, 8, false))
        .add(std::string(ch::kPredictionError), prediction_error(cycle, 8))
        .add(ch::camera_status("cam_left"), camera("cam_left", Cam::STATE_ACTIVE))
        .add(ch::iiwa_status("LEFT"), arm_status(0.0))
        .add(ch::gripper_status("LEFT"), gripper_status(true))
        .add(std::string(ch::kCellState), cell_state(cycle, C::STATE_RUNNING, ""));
  }
  cycles.add(std::string(ch::kSimTruth), sheet(2, S::SOURCE_OBSERVED, 8, true))
      .add(std::string(ch::kCellState), cell_state(3, C::STATE_DEGRADED, "camera cam_right lost"));
  cycles.write(corpus / "lcm_monitor" / "seed_cycles");
  Records learning(m);
  learning.add(std::string(ch::kCellCalibration), calibration())
      .add(std::string(ch::kCellDiagnosis), diagnosis())
      .add(ch::camera_status("cam_right"), camera("cam_right", Cam::STATE_LOST))
      .add(ch::iiwa_status("CENTER"), arm_status(0.5));
  learning.write(corpus / "lcm_monitor" / "seed_learning");

  // The cell: truth, faults, arm and gripper statuses.
  const auto c = fuzz::cell_channels(config.hardware);
  Records cell(c);
  cell.add(std::string(ch::kSimTruth), sheet(1, S::SOURCE_OBSERVED, 8, true))
      .add(std::string(ch::kSimFault), fault("twin", "diverge", true))
      .add(std::string(ch::kSimFault), fault("twin", "slow", false))
      .add(std::string(ch::kSimFault), fault("twin", "melt", true));
  for (const auto& arm : config.hardware.arms) cell.add(ch::iiwa_status(arm.name), arm_status(0.2));
  for (const auto& g : config.hardware.grippers) cell.add(ch::gripper_status(g.name), gripper_status(g.name != "MANUAL"));
  prepreg_lcm::sim_clock_t clock{};
  clock.utime = kUtime;
  clock.sim_us = 1'500'000;
  clock.real_time_factor = 0.5;
  clock.state = prepreg_lcm::sim_clock_t::STATE_HELD;
  clock.held_by = "cell_controller";
  cell.add(std::string(ch::kSimClock), clock);
  cell.write(corpus / "lcm_cell" / "seed_statuses");

  // The world: commands and faults.
  const auto w = fuzz::world_channels(config.hardware);
  Records world(w);
  for (const auto& arm : config.hardware.arms) {
    world.add(ch::iiwa_command(arm.name), drivers::make_iiwa_command(kUtime, joints(0.3)));
  }
  for (const auto& g : config.hardware.grippers) world.add(ch::gripper_command(g.name), gripper_command(G::ACTION_CLOSE));
  world.add(std::string(ch::kSimFault), fault("cam_left", "frozen", true))
      .add(std::string(ch::kSimFault), fault(config.hardware.arms.front().name.c_str(), "status_silent", true))
      .add(ch::gripper_command(config.hardware.grippers.front().name), gripper_command(G::ACTION_OPEN));
  prepreg_lcm::sim_clock_hold_t hold{};
  hold.utime = kUtime;
  hold.client = "cell_controller";
  hold.until_utime = kUtime + 100'000;
  world.add(std::string(ch::kSimClockHold), hold);
  hold.leaving = true;
  world.add(std::string(ch::kSimClockHold), hold);
  world.write(corpus / "lcm_world" / "seed_commands");

  // A log: a few cycles of the cell's own channels, 3 vertices (lcm_log_fuzz.cc's mesh size).
  std::vector<std::pair<std::string, std::string>> events;
  for (std::int64_t cycle = 1; cycle <= 3; ++cycle) {
    events.emplace_back(std::string(ch::kSheetObserved), encode(sheet(cycle, S::SOURCE_OBSERVED, 3, true)));
    events.emplace_back(std::string(ch::kSheetPredicted), encode(sheet(cycle, S::SOURCE_PREDICTED, 3, false)));
    events.emplace_back(ch::iiwa_status("LEFT"), encode(arm_status(0.1)));
    events.emplace_back(ch::gripper_status("LEFT"), encode(gripper_status(true)));
    events.emplace_back(std::string(ch::kSimTruth), encode(sheet(cycle, S::SOURCE_OBSERVED, 3, true)));
    events.emplace_back(std::string(ch::kCellState), encode(cell_state(cycle, C::STATE_RUNNING, "")));
  }
  write_log(corpus / "lcm_log" / "seed_cycles", events);
  std::printf("make_lcm_seeds: wrote the seeds of lcm_monitor, lcm_cell, lcm_world and lcm_log under %s\n",
              corpus.c_str());
  return 0;
}
