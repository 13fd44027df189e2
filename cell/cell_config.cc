#include "cell/cell_config.h"

#include <filesystem>
#include <stdexcept>

#include "drivers/camera_config_json.h"
#include "tracking/tracker_config_json.h"
#include "twin/base/json_field.h"
#include "twin/diagnosis/effect_library.h"

namespace cell {
namespace {

std::string resolve(const std::filesystem::path& base, const std::string& file) {
  const std::filesystem::path p(file);
  return p.is_absolute() ? p.string() : (base / p).lexically_normal().string();
}

void read_cell_settings(const twin::JsonField& f, CellSettings& s) {
  f.only_keys({"lcm_url", "clock", "sim_clock_timeout_s", "cycle_hz", "min_cameras", "robot_status_timeout_ms", "camera_stale_ms",
               "startup_timeout_s", "camera_startup_timeout_s", "arm_status_timeout_s",
               "hold_tolerance_m", "move_speed_m_s", "joint_speed_scale", "release_timeout_s",
               "twin_lockstep", "twin_priority", "twin_background_factorization"});
  if (auto v = f.optional("lcm_url")) s.lcm_url = v->string();
  if (auto v = f.optional("clock")) {
    const std::optional<drivers::ClockSource> clock = drivers::clock_source_from_name(v->string());
    if (!clock) v->fail("must be \"wall\" (real hardware) or \"sim\" (the fake world's SIM_CLOCK)");
    s.clock = *clock;
  }
  if (auto v = f.optional("sim_clock_timeout_s")) s.sim_clock_timeout_s = v->positive("s");
  if (auto v = f.optional("cycle_hz")) s.cycle_hz = v->positive("1/s");
  if (auto v = f.optional("min_cameras")) s.min_cameras = v->positive_integer();
  if (auto v = f.optional("robot_status_timeout_ms")) s.robot_status_timeout_ms = v->positive("ms");
  if (auto v = f.optional("camera_stale_ms")) s.camera_stale_ms = v->positive("ms");
  if (auto v = f.optional("startup_timeout_s")) s.startup_timeout_s = v->positive("s");
  if (auto v = f.optional("camera_startup_timeout_s")) s.camera_startup_timeout_s = v->positive("s");
  if (auto v = f.optional("arm_status_timeout_s")) s.arm_status_timeout_s = v->positive("s");
  if (auto v = f.optional("hold_tolerance_m")) s.hold_tolerance_m = v->positive("m");
  if (auto v = f.optional("move_speed_m_s")) {
    s.move_speed_m_s = v->positive("m/s");
    if (s.move_speed_m_s > 0.05) v->fail("must be at most 0.05 m/s (the experiment's speed limit)");
  }
  if (auto v = f.optional("joint_speed_scale")) {
    s.joint_speed_scale = v->positive("");
    if (s.joint_speed_scale > 1.0) v->fail("must be in (0, 1]");
  }
  if (auto v = f.optional("release_timeout_s")) s.release_timeout_s = v->positive("s");
  if (auto v = f.optional("twin_lockstep")) {
    if (!v->json().is_boolean()) v->fail("must be true or false");
    s.twin_lockstep = v->json().get<bool>();
    if (!s.twin_lockstep && s.clock == drivers::ClockSource::kSim) {
      v->fail("must be true on \"clock\": \"sim\" (a step taken up whenever the wall lets it would make runs differ)");
    }
  }
  // On the simulation clock the twin steps in lockstep: which cycle takes up a step must not
  // depend on the wall.
  if (s.clock == drivers::ClockSource::kSim) s.twin_lockstep = true;
  if (auto v = f.optional("twin_background_factorization")) {
    if (!v->json().is_boolean()) v->fail("must be true or false");
    s.twin_background_factorization = v->json().get<bool>();
  }
  if (auto v = f.optional("twin_priority")) {
    const std::optional<WorkerPriority> priority = worker_priority_from_name(v->string());
    if (!priority) v->fail("must be \"idle\" or \"normal\"");
    s.twin_priority = *priority;
  }
}

bool boolean(const twin::JsonField& v) {
  if (!v.json().is_boolean()) v.fail("must be true or false");
  return v.json().get<bool>();
}

void read_learning_settings(const twin::JsonField& f, LearningSettings& s) {
  f.only_keys({"record_states", "calibrate", "window_s", "min_still_s", "max_states", "min_gain", "max_evaluations",
               "parameters", "diagnose", "diagnosis_effects", "diagnosis_noise_mm", "diagnosis_max_evaluations",
               "follow_branches",
               "reseed_min_error_m", "reseed_min_gain", "priority"});
  if (auto v = f.optional("priority")) {
    const std::optional<WorkerPriority> priority = worker_priority_from_name(v->string());
    if (!priority) v->fail("must be \"idle\" or \"normal\"");
    s.priority = *priority;
  }
  if (auto v = f.optional("follow_branches")) s.follow_branches = boolean(*v);
  if (auto v = f.optional("reseed_min_error_m")) s.reseed_min_error_m = v->positive("m");
  if (auto v = f.optional("reseed_min_gain")) {
    s.reseed_min_gain = v->non_negative("");
    if (s.reseed_min_gain >= 1.0) v->fail("must be in [0, 1)");
  }
  if (auto v = f.optional("record_states")) s.record_states = boolean(*v);
  if (auto v = f.optional("calibrate")) s.calibrate = boolean(*v);
  if (auto v = f.optional("window_s")) s.settle.window_s = v->positive("s");
  if (auto v = f.optional("min_still_s")) s.settle.min_still_s = v->non_negative("s");
  if (auto v = f.optional("max_states")) s.max_states = v->positive_integer();
  if (auto v = f.optional("min_gain")) {
    s.calibration.min_gain = v->non_negative("");
    if (s.calibration.min_gain >= 1.0) v->fail("must be in [0, 1)");
  }
  if (auto v = f.optional("max_evaluations")) s.calibration.max_evaluations = v->positive_integer();
  if (auto v = f.optional("parameters")) {
    if (!v->is_array() || v->array_size() == 0) v->fail("must be a non-empty array of parameter names");
    s.calibration.parameters.clear();
    for (std::size_t i = 0; i < v->array_size(); ++i) {
      try {
        s.calibration.parameters.push_back(twin::parse_material_parameter((*v)[i].string()));
      } catch (const std::invalid_argument& e) {
        (*v)[i].fail(e.what());
      }
    }
  }
  if (auto v = f.optional("diagnose")) s.diagnose = boolean(*v);
  if (auto v = f.optional("diagnosis_noise_mm")) s.diagnosis.noise_mm = v->positive("mm");
  if (auto v = f.optional("diagnosis_max_evaluations")) {
    s.diagnosis.base_evaluations = s.diagnosis.refit_evaluations = v->positive_integer();
  }
  if (auto v = f.optional("diagnosis_effects")) {
    if (!v->is_array() || v->array_size() == 0) v->fail("must be a non-empty array of effect names");
    std::string list;
    for (std::size_t i = 0; i < v->array_size(); ++i) {
      const std::string name = (*v)[i].string();
      try {
        twin::diagnosis::find_effect(name);
      } catch (const std::invalid_argument& e) {
        (*v)[i].fail(e.what());
      }
      list += (list.empty() ? "" : ",") + name;
    }
    s.diagnosis.effects = list;
  }
  if (s.diagnose && !s.record_states) f.fail_child("diagnose", "needs record_states (it diagnoses the recorded states)");
  if (s.calibrate && !s.record_states) f.fail_child("calibrate", "needs record_states (it fits the recorded states)");
  if (s.follow_branches && !s.record_states) {
    f.fail_child("follow_branches", "needs record_states (it re-seeds from a settled state)");
  }
}

}  // namespace

CellConfig read_cell_config(const std::string& path) {
  const nlohmann::json doc = twin::JsonField::parse_file(path);
  const twin::JsonField root(doc, path);
  root.only_keys({"cell", "twin", "job", "tracker", "learning", "cameras", "arms", "grippers"});
  const std::filesystem::path base = std::filesystem::path(path).parent_path();

  CellConfig c;
  c.path = path;
  if (auto f = root.optional("cell")) read_cell_settings(*f, c.cell);

  const twin::JsonField tw = root["twin"];
  tw.only_keys({"material_file", "sheet"});
  c.material_file = resolve(base, tw["material_file"].string());
  c.sheet = twin::read_sheet_spec(tw["sheet"], base.string());
  c.sheet_placement_given = tw["sheet"].has("placement");

  const twin::JsonField job = root["job"];
  job.only_keys({"plan_file", "experiment_file"});
  c.plan_file = resolve(base, job["plan_file"].string());
  if (auto e = job.optional("experiment_file")) c.experiment_file = resolve(base, e->string());

  if (auto t = root.optional("tracker")) {
    try {
      c.tracker = t->is_string() ? tracking::load_tracker_config(resolve(base, t->string()))
                                 : tracking::parse_tracker_config(t->json().dump(), path + " (tracker)");
    } catch (const std::exception& e) {
      throw std::invalid_argument(path + ": field 'tracker': " + e.what());
    }
  }
  if (auto l = root.optional("learning")) read_learning_settings(*l, c.learning);
  c.cameras = drivers::parse_camera_configs(doc, path);
  if (c.cameras.empty()) root.fail_child("cameras", "must list at least one camera");
  if (c.cell.min_cameras > static_cast<int>(c.cameras.size())) {
    root["cell"]["min_cameras"].fail("exceeds the number of cameras (" +
                                     std::to_string(c.cameras.size()) + ")");
  }
  c.hardware = drivers::parse_cell_hardware(doc, path);
  return c;
}

}  // namespace cell
