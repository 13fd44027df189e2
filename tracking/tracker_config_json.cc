// JSON -> TrackerConfig with field-named errors.
#include "tracking/tracker_config_json.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace tracking {
namespace {

using nlohmann::json;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Reads the fields of one JSON object, remembering which it used so the rest can be reported.
class Fields {
 public:
  Fields(const json& object, std::string path, const std::string& source)
      : object_(object), path_(std::move(path)), source_(source) {
    if (!object_.is_object()) fail(path_.empty() ? "the document" : path_, "an object");
  }

  void number(const char* key, double& out, double lo, double hi, bool open_lo = false) {
    const json* v = find(key);
    if (!v) return;
    const std::string what = open_lo ? fmt::format("a number > {} and <= {}", lo, hi)
                                     : fmt::format("a number in [{}, {}]", lo, hi);
    if (!v->is_number()) fail(name(key), what, v);
    const double x = v->get<double>();
    if (!std::isfinite(x) || x > hi || x < lo || (open_lo && x == lo)) fail(name(key), what, v);
    out = x;
  }
  void integer(const char* key, int& out, int lo, int hi) {
    const json* v = find(key);
    if (!v) return;
    const std::string what = fmt::format("an integer in [{}, {}]", lo, hi);
    if (!v->is_number_integer()) fail(name(key), what, v);
    const long long x = v->get<long long>();
    if (x < lo || x > hi) fail(name(key), what, v);
    out = static_cast<int>(x);
  }
  void boolean(const char* key, bool& out) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_boolean()) fail(name(key), "true or false", v);
    out = v->get<bool>();
  }
  void vec3(const char* key, Vec3& out) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_array() || v->size() != 3) fail(name(key), "an array of 3 numbers [x, y, z] (m)", v);
    for (int k = 0; k < 3; ++k) {
      if (!(*v)[k].is_number() || !std::isfinite((*v)[k].get<double>())) {
        fail(name(key), "an array of 3 finite numbers [x, y, z] (m)", v);
      }
      out[k] = (*v)[k].get<double>();
    }
  }
  const json* find(const char* key) {
    used_.insert(key);
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }
  Fields child(const char* key) {
    const json* v = find(key);
    static const json empty = json::object();
    return Fields(v ? *v : empty, name(key), source_);
  }
  std::string name(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  // Call after reading every known field: anything left is a misspelling or a foreign field.
  void no_others() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!used_.count(it.key())) {
        throw std::runtime_error(
            fmt::format("{}: unknown field '{}'", source_, name(it.key().c_str())));
      }
    }
  }
  [[noreturn]] void fail(const std::string& field, const std::string& expected,
                         const json* got = nullptr) const {
    throw std::runtime_error(fmt::format("{}: field '{}': expected {}{}", source_, field, expected,
                                         got ? ", got " + got->dump() : std::string()));
  }

 private:
  const json& object_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> used_;
};

void read_color(Fields f, ColorRule& c) {
  f.boolean("enabled", c.enabled);
  f.number("max_value", c.max_value, 0.0, 1.0);
  f.number("min_value", c.min_value, 0.0, 1.0);
  f.number("min_saturation", c.min_saturation, 0.0, 1.0);
  f.number("max_saturation", c.max_saturation, 0.0, 1.0);
  if (const json* hue = f.find("hue_deg")) {
    const auto in_range = [](const json& h) {
      return h.is_number() && h.get<double>() >= 0.0 && h.get<double>() <= 360.0;
    };
    if (!hue->is_array() || hue->size() != 2 || !in_range((*hue)[0]) || !in_range((*hue)[1])) {
      f.fail(f.name("hue_deg"), "[min, max] in degrees within [0, 360] (min > max wraps through 0)",
             hue);
    }
    c.use_hue = true;
    c.min_hue_deg = (*hue)[0].get<double>();
    c.max_hue_deg = (*hue)[1].get<double>();
  }
  if (const json* unknown = f.find("unknown")) {
    if (*unknown == "keep") {
      c.unknown = UnknownColorPolicy::kKeep;
    } else if (*unknown == "reject") {
      c.unknown = UnknownColorPolicy::kReject;
    } else {
      f.fail(f.name("unknown"), "\"keep\" or \"reject\"", unknown);
    }
  }
  f.no_others();
}

}  // namespace

TrackerConfig parse_tracker_config(const std::string& text, const std::string& source) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number beyond a double
    throw std::runtime_error(fmt::format("{}: not valid JSON: {}", source, e.what()));
  }
  TrackerConfig c;
  Fields root(doc, "", source);
  {
    Fields f = root.child("fusion");
    f.integer("pixel_stride", c.fusion.pixel_stride, 1, 16);
    f.number("min_depth_m", c.fusion.min_depth_m, 0.0, 65.0);
    f.number("max_depth_m", c.fusion.max_depth_m, 0.0, 65.0, true);
    f.no_others();
    if (c.fusion.max_depth_m <= c.fusion.min_depth_m) {
      f.fail("fusion.max_depth_m", "a depth above fusion.min_depth_m");
    }
  }
  {
    Fields f = root.child("segmentation");
    f.vec3("box_min_m", c.segmentation.box_min_m);
    f.vec3("box_max_m", c.segmentation.box_max_m);
    read_color(f.child("color"), c.segmentation.color);
    f.no_others();
    if ((c.segmentation.box_max_m.array() <= c.segmentation.box_min_m.array()).any()) {
      f.fail("segmentation.box_max_m", "every coordinate above segmentation.box_min_m's");
    }
  }
  {
    Fields f = root.child("resample");
    f.number("voxel_m", c.resample.voxel_m, 0.0, 1.0);
    f.boolean("remove_outliers", c.resample.remove_outliers);
    f.integer("outlier_neighbours", c.resample.outlier_neighbours, 1, 1000);
    f.number("outlier_stddev", c.resample.outlier_stddev, 0.0, 100.0, true);
    f.no_others();
  }
  {
    Fields f = root.child("registration");
    RegistrationOptions& r = c.registration;
    f.integer("max_iterations", r.max_iterations, 1, 100);
    f.number("initial_gate_m", r.initial_gate_m, 0.0, 10.0, true);
    f.number("final_gate_m", r.final_gate_m, 0.0, 10.0, true);
    f.number("smoothing_length_m", r.smoothing_length_m, 0.0, 10.0);
    f.number("smoothness_weight", r.smoothness_weight, 0.0, kInf);
    f.number("point_weight", r.point_weight, 0.0, kInf);
    f.number("border_point_weight", r.border_point_weight, 0.0, kInf);
    f.number("cloud_to_surface_weight", r.cloud_to_surface_weight, 0.0, kInf);
    f.number("stretch_weight", r.stretch_weight, 0.0, kInf);
    f.boolean("use_rest_lengths", r.use_rest_lengths);
    f.integer("cloud_stride", r.cloud_stride, 1, 1000);
    f.number("prior_weight", r.prior_weight, 0.0, kInf, true);
    f.number("converged_step_m", r.converged_step_m, 0.0, 1.0);
    f.number("observed_distance_m", r.observed_distance_m, 0.0, 1.0, true);
    f.boolean("warm_start", r.warm_start);
    f.number("warm_gate_m", r.warm_gate_m, 0.0, 10.0, true);
    f.integer("warm_max_iterations", r.warm_max_iterations, 1, 100);
    f.number("warm_min_matched_fraction", r.warm_min_matched_fraction, 0.0, 1.0);
    f.no_others();
    if (r.final_gate_m > r.initial_gate_m) {
      f.fail("registration.final_gate_m", "at most registration.initial_gate_m");
    }
  }
  {
    Fields f = root.child("coverage");
    f.number("radius_m", c.coverage.radius_m, 0.0, 1.0, true);
    f.integer("min_points", c.coverage.min_points, 1, 10000);
    f.no_others();
  }
  {
    Fields f = root.child("calibration");
    CalibrationCheckOptions& k = c.calibration;
    f.boolean("enabled", k.enabled);
    f.integer("every_n_cycles", k.every_n_cycles, 1, 1000000);
    f.number("voxel_m", k.voxel_m, 0.0, 1.0);
    f.number("plane_radius_m", k.plane_radius_m, 0.0, 1.0, true);
    f.integer("min_plane_points", k.min_plane_points, 3, 100000);
    f.integer("min_overlap_points", k.min_overlap_points, 1, 100000000);
    f.integer("max_points", k.max_points, 1, 100000000);
    f.number("max_median_m", k.max_median_m, 0.0, 1.0, true);
    f.number("max_p90_m", k.max_p90_m, 0.0, 1.0, true);
    f.no_others();
  }
  root.integer("min_sheet_points", c.min_sheet_points, 1, 100000000);
  root.no_others();
  return c;
}

TrackerConfig load_tracker_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the tracker config", path));
  std::stringstream text;
  text << in.rdbuf();
  return parse_tracker_config(text.str(), path);
}

}  // namespace tracking
