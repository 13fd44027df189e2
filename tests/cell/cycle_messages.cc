// Made-up cell cycles for the monitor tests.
#include "tests/cell/cycle_messages.h"

#include <algorithm>
#include <cmath>

#include "drivers/lcm_channels.h"

namespace testing_support {

namespace ch = drivers::channels;
using prepreg_lcm::camera_status_t;
using prepreg_lcm::sheet_state_t;

CycleMessages make_cycle(std::int64_t cycle_id, std::int64_t utime, std::mt19937& rng, int grid,
                         const std::string& lost_camera) {
  CycleMessages c;
  std::normal_distribution<float> noise_m(0.0f, 0.004f);
  std::bernoulli_distribution seen(0.8);
  const std::int64_t frames_utime = utime - 40'000;
  auto init = [&](sheet_state_t& s, std::int8_t source, std::int64_t t) {
    s.utime = t;
    s.cycle_id = cycle_id;
    s.source = source;
    s.num_vertices = grid * grid;
    s.num_observed_flags = 0;  // set for the observed sheet once its flags exist
  };
  init(c.observed, sheet_state_t::SOURCE_OBSERVED, frames_utime);
  init(c.predicted, sheet_state_t::SOURCE_PREDICTED, frames_utime);
  double sum = 0.0, worst = 0.0;
  int compared = 0;
  for (int i = 0; i < grid; ++i) {
    for (int j = 0; j < grid; ++j) {
      // A 0.5 m sheet hanging in the x-z plane with a little sag.
      const float x = 0.5f * i / (grid - 1), z = 1.5f - 0.5f * j / (grid - 1);
      const float y = 0.03f * std::sin(3.1416f * x / 0.5f);
      c.predicted.x_m.push_back(x);
      c.predicted.y_m.push_back(y);
      c.predicted.z_m.push_back(z);
      const float ox = x + noise_m(rng), oy = y + noise_m(rng), oz = z + noise_m(rng);
      c.observed.x_m.push_back(ox);
      c.observed.y_m.push_back(oy);
      c.observed.z_m.push_back(oz);
      const bool observed = seen(rng);
      c.observed.vertex_observed.push_back(observed);
      if (!observed) continue;
      // Distance as the receiver computes it: from the float positions on the wire.
      const double d = std::sqrt(std::pow(double(ox) - x, 2) + std::pow(double(oy) - y, 2) +
                                 std::pow(double(oz) - z, 2));
      sum += d;
      worst = std::max(worst, d);
      ++compared;
    }
  }
  c.observed.num_observed_flags = grid * grid;
  c.observed.coverage = static_cast<float>(compared) / (grid * grid);
  c.predicted.coverage = 1.0f;

  c.error.utime = utime;
  c.error.cycle_id = cycle_id;
  c.error.frames_utime = frames_utime;
  c.error.prediction_utime = frames_utime;
  c.error.num_compared = compared;
  c.error.mean_m = static_cast<float>(compared ? sum / compared : 0.0);
  c.error.max_m = static_cast<float>(worst);
  c.error.score_m = static_cast<float>(compared ? sum / compared + 0.5 * worst : 0.0);
  c.error.num_vertex_errors = 0;

  for (const char* name : {"cam_left", "cam_center", "cam_right"}) {
    camera_status_t s{};
    s.utime = utime;
    s.name = name;
    const bool lost = lost_camera == name;
    s.state = lost ? camera_status_t::STATE_LOST : camera_status_t::STATE_ACTIVE;
    s.frames = cycle_id + 1;
    s.last_frame_utime = frames_utime;
    s.message = lost ? "no frame within 1 s" : "";
    c.cameras.emplace_back(name, s);
  }

  c.arm.utime = utime;
  c.arm.num_joints = 7;
  for (auto* v :
       {&c.arm.joint_position_measured, &c.arm.joint_velocity_estimated,
        &c.arm.joint_position_commanded, &c.arm.joint_position_ipo, &c.arm.joint_torque_measured,
        &c.arm.joint_torque_commanded, &c.arm.joint_torque_external}) {
    v->assign(7, 0.1);
  }

  c.state = prepreg_lcm::cell_state_t{};
  c.state.utime = utime;
  c.state.cycle_id = cycle_id;
  c.state.state = lost_camera.empty() ? prepreg_lcm::cell_state_t::STATE_RUNNING
                                      : prepreg_lcm::cell_state_t::STATE_DEGRADED;
  c.state.reason = lost_camera.empty() ? "" : "camera " + lost_camera + " lost";
  c.state.cameras_ok = lost_camera.empty();
  c.state.tracker_ok = c.state.twin_ok = c.state.robots_ok = c.state.grippers_ok = true;
  c.state.num_cameras = 3;
  c.state.num_cameras_ok = lost_camera.empty() ? 3 : 2;
  return c;
}

std::vector<EncodedMessage> encode_cycle(const CycleMessages& c) {
  std::vector<EncodedMessage> out;
  out.push_back({std::string(ch::kSheetObserved), encode_message(c.observed)});
  out.push_back({std::string(ch::kSheetPredicted), encode_message(c.predicted)});
  out.push_back({std::string(ch::kPredictionError), encode_message(c.error)});
  for (const auto& [name, status] : c.cameras) {
    out.push_back({ch::camera_status(name), encode_message(status)});
  }
  out.push_back({ch::iiwa_status("LEFT"), encode_message(c.arm)});
  out.push_back({ch::iiwa_status("RIGHT"), encode_message(c.arm)});
  out.push_back({std::string(ch::kCellState), encode_message(c.state)});
  return out;
}

bool publish_cycle(drivers::LcmBus& bus, const CycleMessages& c) {
  bool ok = true;
  for (const EncodedMessage& m : encode_cycle(c)) {
    ok &= bus.publish_raw(m.channel, m.bytes.data(), m.bytes.size());
  }
  return ok;
}

}  // namespace testing_support
