#include "cell/cell_messages.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cell {

prepreg_lcm::sheet_state_t predicted_sheet(std::int64_t utime, std::int64_t cycle, const twin::VecX& x) {
  prepreg_lcm::sheet_state_t m{};
  m.utime = utime;
  m.cycle_id = cycle;
  m.source = prepreg_lcm::sheet_state_t::SOURCE_PREDICTED;
  m.num_vertices = static_cast<int>(x.size() / 3);
  for (int i = 0; i < m.num_vertices; ++i) {
    m.x_m.push_back(static_cast<float>(x[3 * i]));
    m.y_m.push_back(static_cast<float>(x[3 * i + 1]));
    m.z_m.push_back(static_cast<float>(x[3 * i + 2]));
  }
  m.num_observed_flags = 0;
  m.coverage = 1.0f;
  return m;
}

prepreg_lcm::sheet_state_t observed_sheet(std::int64_t utime, std::int64_t cycle,
                                          const tracking::TrackResult& r) {
  prepreg_lcm::sheet_state_t m{};
  m.utime = utime;
  m.cycle_id = cycle;
  m.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  m.num_vertices = static_cast<int>(r.vertices_m.size());
  for (const auto& v : r.vertices_m) {
    m.x_m.push_back(static_cast<float>(v.x()));
    m.y_m.push_back(static_cast<float>(v.y()));
    m.z_m.push_back(static_cast<float>(v.z()));
  }
  const bool flags = r.vertex_observed.size() == r.vertices_m.size();
  m.num_observed_flags = flags ? m.num_vertices : 0;
  if (flags) {
    for (auto o : r.vertex_observed) m.vertex_observed.push_back(o != 0);
  }
  m.coverage = static_cast<float>(std::clamp(r.coverage.fraction, 0.0, 1.0));
  return m;
}

VertexError vertex_error(const tracking::TrackResult& r) {
  VertexError e;
  const auto& d = r.prediction_error.per_vertex_norm_m;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  e.per_vertex_m.assign(r.vertices_m.size(), nan);
  double sum = 0;
  for (std::size_t i = 0; i < d.size() && i < r.vertex_observed.size(); ++i) {
    if (!r.vertex_observed[i] || !std::isfinite(d[i])) continue;
    e.per_vertex_m[i] = static_cast<float>(d[i]);
    sum += d[i];
    e.max_m = std::max(e.max_m, d[i]);
    ++e.compared;
  }
  if (e.compared > 0) e.mean_m = sum / e.compared;
  return e;
}

prepreg_lcm::prediction_error_t prediction_error(std::int64_t utime, std::int64_t cycle,
                                                 std::int64_t frames_utime,
                                                 std::int64_t prediction_utime, const VertexError& e) {
  prepreg_lcm::prediction_error_t m{};
  m.utime = utime;
  m.cycle_id = cycle;
  m.frames_utime = frames_utime;
  m.prediction_utime = prediction_utime;
  m.num_compared = e.compared;
  m.mean_m = static_cast<float>(e.mean_m);
  m.max_m = static_cast<float>(e.max_m);
  m.score_m = static_cast<float>(e.mean_m + 0.5 * e.max_m);
  m.num_vertex_errors = static_cast<int>(e.per_vertex_m.size());
  m.vertex_error_m = e.per_vertex_m;
  return m;
}

prepreg_lcm::camera_status_t camera_status(std::int64_t utime, const std::string& name,
                                           const drivers::CameraHealth& h, bool stale,
                                           bool frozen, std::int64_t last_frame_utime) {
  prepreg_lcm::camera_status_t m{};
  m.utime = utime;
  m.name = name;
  m.state = static_cast<std::int8_t>(h.state);
  m.frames = static_cast<std::int64_t>(h.frames);
  m.dropped = static_cast<std::int64_t>(h.dropped);
  m.stale = stale;
  m.frozen = frozen;
  m.last_frame_utime = last_frame_utime;
  m.message = h.message;
  return m;
}

prepreg_lcm::cell_state_t cell_state(std::int64_t utime, const CellStatus& s) {
  prepreg_lcm::cell_state_t m{};
  m.utime = utime;
  m.cycle_id = s.cycle;
  m.state = static_cast<std::int8_t>(s.state);
  m.reason = s.reason;
  m.cameras_ok = s.cameras_ok;
  m.tracker_ok = s.tracker_ok;
  m.twin_ok = s.twin_ok;
  m.robots_ok = s.robots_ok;
  m.grippers_ok = s.grippers_ok;
  m.num_cameras_ok = static_cast<std::int8_t>(std::clamp(s.cameras_fresh, 0, 127));
  m.num_cameras = static_cast<std::int8_t>(std::clamp(s.cameras, 0, 127));
  m.twin_reseeds = s.twin_reseeds;
  return m;
}

prepreg_lcm::grasp_plan_t grasp_plan_message(std::int64_t utime, std::int64_t plan_id,
                                             const twin::GraspPlan& plan,
                                             const drivers::CellHardwareConfig& hardware) {
  prepreg_lcm::grasp_plan_t m{};
  m.utime = utime;
  m.plan_id = plan_id;
  m.num_grasps = static_cast<int>(plan.grasps.size());
  for (const auto& g : plan.grasps) {
    m.material_u_m.push_back(static_cast<float>(g.clamp.material_point_m.x()));
    m.material_v_m.push_back(static_cast<float>(g.clamp.material_point_m.y()));
    m.cell_x_m.push_back(static_cast<float>(g.hold_position_m.x()));
    m.cell_y_m.push_back(static_cast<float>(g.hold_position_m.y()));
    m.cell_z_m.push_back(static_cast<float>(g.hold_position_m.z()));
    const drivers::GripperConfig* gc = hardware.find_gripper(g.gripper);
    m.arm.push_back(gc && !gc->arm.empty() ? gc->arm : g.gripper);  // the operator: its gripper name
  }
  m.predicted_sag_m = std::isfinite(plan.predicted_sag_m) ? static_cast<float>(plan.predicted_sag_m) : 0.0f;
  m.feasible = plan.feasible;
  m.note = plan.note;
  return m;
}

}  // namespace cell
