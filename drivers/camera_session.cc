#include "drivers/camera_session.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace drivers {
namespace {

using nlohmann::json;

json intrinsics_json(const Intrinsics& k) {
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy},
          {"k1", k.k1}, {"k2", k.k2}, {"p1", k.p1}, {"p2", k.p2}, {"k3", k.k3}};
}

json mode_json(const StreamMode& m) { return {{"width", m.width}, {"height", m.height}, {"fps", m.fps}}; }

json pose_json(const Eigen::Isometry3d& t) {
  json a = json::array();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a.push_back(t.matrix()(r, c));
  }
  return a;
}

// Field access that names session.json and the field on failure.
struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw std::runtime_error(fmt::format("{}: field '{}' {}", file, field, what));
  }
  const json& at(const json& obj, const std::string& key, const std::string& field) const {
    if (!obj.is_object()) fail(field, "must be an object");
    if (!obj.contains(key)) fail(field + "." + key, "is missing");
    return obj.at(key);
  }
  double number(const json& obj, const std::string& key, const std::string& field) const {
    const json& v = at(obj, key, field);
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(field + "." + key, "must be a finite number");
    return v.get<double>();
  }
  int integer(const json& obj, const std::string& key, const std::string& field) const {
    const json& v = at(obj, key, field);
    if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 100000) {
      fail(field + "." + key, "must be an integer in 0..100000");
    }
    return int(v.get<long long>());
  }
  Intrinsics intrinsics(const json& obj, const std::string& field) const {
    Intrinsics k;
    k.width = integer(obj, "width", field);
    k.height = integer(obj, "height", field);
    k.fx = number(obj, "fx", field);
    k.fy = number(obj, "fy", field);
    k.cx = number(obj, "cx", field);
    k.cy = number(obj, "cy", field);
    k.k1 = number(obj, "k1", field);
    k.k2 = number(obj, "k2", field);
    k.p1 = number(obj, "p1", field);
    k.p2 = number(obj, "p2", field);
    k.k3 = number(obj, "k3", field);
    return k;
  }
  StreamMode mode(const json& obj, const std::string& field) const {
    return {integer(obj, "width", field), integer(obj, "height", field), integer(obj, "fps", field)};
  }
  Eigen::Isometry3d pose(const json& v, const std::string& field) const {
    if (!v.is_array() || v.size() != 16) fail(field, "must be 16 numbers (4x4 row-major)");
    Eigen::Matrix4d m;
    for (int i = 0; i < 16; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) fail(field, "must hold finite numbers");
      m(i / 4, i % 4) = v[i].get<double>();
    }
    if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) fail(field, "must end with the row 0 0 0 1");
    Eigen::Isometry3d t;
    t.matrix() = m;
    return t;
  }
};

}  // namespace

std::string check_camera_name(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return "camera name must not be empty, '.' or '..'";
  for (const char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') {
      return fmt::format("camera name '{}' may only hold letters, digits, '_', '-' and '.'", name);
    }
  }
  return "";
}

std::string write_session(const std::filesystem::path& dir, const std::vector<SessionCamera>& cameras) {
  json doc = {{"format", kSessionFormat}, {"version", kSessionVersion}, {"cameras", json::array()}};
  for (const auto& c : cameras) {
    doc["cameras"].push_back({{"name", c.name},
                              {"index", c.index},
                              {"depth_mode", mode_json(c.depth_mode)},
                              {"color_mode", mode_json(c.color_mode)},
                              {"depth_unit_mm", c.depth_unit_mm},
                              {"depth_intrinsics", intrinsics_json(c.depth_intrinsics)},
                              {"color_intrinsics", intrinsics_json(c.color_intrinsics)},
                              {"depth_to_color", pose_json(c.depth_to_color)},
                              {"camera_to_cell", pose_json(c.camera_to_cell)}});
  }
  // Write beside and rename, so a reader never sees a half-written file.
  const std::filesystem::path file = dir / "session.json", tmp = dir / "session.json.tmp";
  {
    std::ofstream out(tmp);
    out << doc.dump(2) << '\n';
    if (!out) return fmt::format("{}: write failed", tmp.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) return fmt::format("{}: cannot rename into place: {}", file.string(), ec.message());
  return "";
}

std::vector<SessionCamera> read_session(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "session.json";
  const Reader r{file.string()};
  std::ifstream in(file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open (not a recorded session?)", file.string()));
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(fmt::format("{}: not valid JSON: {}", file.string(), e.what()));
  }
  const json& format = r.at(doc, "format", "");
  if (format != kSessionFormat) r.fail("format", fmt::format("must be \"{}\"", kSessionFormat));
  if (r.integer(doc, "version", "") != kSessionVersion) r.fail("version", fmt::format("must be {}", kSessionVersion));
  const json& cams = r.at(doc, "cameras", "");
  if (!cams.is_array()) r.fail("cameras", "must be an array");
  std::vector<SessionCamera> out;
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const std::string f = fmt::format("cameras[{}]", i);
    const json& c = cams[i];
    SessionCamera s;
    const json& name = r.at(c, "name", f);
    if (!name.is_string()) r.fail(f + ".name", "must be a string");
    s.name = name.get<std::string>();
    if (const std::string why = check_camera_name(s.name); !why.empty()) r.fail(f + ".name", why);
    const json& index = r.at(c, "index", f);
    if (!index.is_string()) r.fail(f + ".index", "must be a string (path relative to the session)");
    s.index = index.get<std::string>();
    s.depth_mode = r.mode(r.at(c, "depth_mode", f), f + ".depth_mode");
    s.color_mode = r.mode(r.at(c, "color_mode", f), f + ".color_mode");
    s.depth_unit_mm = r.number(c, "depth_unit_mm", f);
    if (!(s.depth_unit_mm > 0)) r.fail(f + ".depth_unit_mm", "must be > 0");
    s.depth_intrinsics = r.intrinsics(r.at(c, "depth_intrinsics", f), f + ".depth_intrinsics");
    if (s.depth_intrinsics.width <= 0 || s.depth_intrinsics.height <= 0) {
      r.fail(f + ".depth_intrinsics", "must have a positive width and height");
    }
    s.color_intrinsics = r.intrinsics(r.at(c, "color_intrinsics", f), f + ".color_intrinsics");
    s.depth_to_color = r.pose(r.at(c, "depth_to_color", f), f + ".depth_to_color");
    s.camera_to_cell = r.pose(r.at(c, "camera_to_cell", f), f + ".camera_to_cell");
    out.push_back(std::move(s));
  }
  return out;
}

std::string format_index_line(const SessionIndexEntry& e) {
  return fmt::format("{} {} {} {} {}", e.sequence, e.device_time_us, e.host_time_us, e.depth_file,
                     e.color_file.empty() ? "-" : e.color_file);
}

std::vector<SessionIndexEntry> read_session_index(const std::filesystem::path& index_file) {
  std::ifstream in(index_file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", index_file.string()));
  std::vector<SessionIndexEntry> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    SessionIndexEntry e;
    std::string extra;
    if (!(s >> e.sequence >> e.device_time_us >> e.host_time_us >> e.depth_file >> e.color_file) || (s >> extra)) {
      throw std::runtime_error(fmt::format(
          "{}:{}: expected 'sequence device_time_us host_time_us depth_file color_file', got '{}'",
          index_file.string(), number, line));
    }
    if (e.color_file == "-") e.color_file.clear();
    for (const std::string* name : {&e.depth_file, &e.color_file}) {
      if (name->find('/') != std::string::npos || *name == "..") {
        throw std::runtime_error(fmt::format("{}:{}: file name '{}' must not contain a directory",
                                             index_file.string(), number, *name));
      }
    }
    // Equal sequences are allowed: a frozen stream may repeat its counter.
    if (!out.empty() && e.sequence < out.back().sequence) {
      throw std::runtime_error(fmt::format("{}:{}: sequence {} goes backwards (previous {})",
                                           index_file.string(), number, e.sequence, out.back().sequence));
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace drivers
