#include "drivers/camera_session.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/durable_file.h"
#include "drivers/json_field.h"

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

Intrinsics read_intrinsics(const JsonField& f) {
  Intrinsics k;
  k.width = f["width"].integer(0, 100000);  // 0: a camera without colour
  k.height = f["height"].integer(0, 100000);
  k.fx = f["fx"].number();
  k.fy = f["fy"].number();
  k.cx = f["cx"].number();
  k.cy = f["cy"].number();
  k.k1 = f["k1"].number();
  k.k2 = f["k2"].number();
  k.p1 = f["p1"].number();
  k.p2 = f["p2"].number();
  k.k3 = f["k3"].number();
  return k;
}

StreamMode read_mode(const JsonField& f) {
  return {f["width"].integer(0, 100000), f["height"].integer(0, 100000), f["fps"].integer(0, 100000)};
}

Eigen::Isometry3d read_pose(const JsonField& f) {
  if (!f.value().is_array() || f.value().size() != 16) f.fail("must be 16 numbers (4x4 row-major)");
  const std::vector<double> v = f.numbers(16);
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = v[i];
  if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) f.fail("must end with the row 0 0 0 1");
  Eigen::Isometry3d t;
  t.matrix() = m;
  return t;
}

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
  // Written beside, flushed and renamed: a reader or a crash never finds a half-written file.
  const std::filesystem::path file = dir / "session.json";
  try {
    prepreg::write_file_atomically(file, doc.dump(2) + "\n");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::vector<SessionCamera> read_session(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "session.json";
  std::ifstream in(file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open (not a recorded session?)", file.string()));
  const json doc = parse_json_stream(in, file.string());
  const JsonField r(doc, file.string());
  if (r["format"].value() != kSessionFormat) r["format"].fail(fmt::format("must be \"{}\"", kSessionFormat));
  if (r["version"].integer(0, 100000) != kSessionVersion) r["version"].fail(fmt::format("must be {}", kSessionVersion));
  const JsonField cams = r["cameras"];
  std::vector<SessionCamera> out;
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const JsonField c = cams.at(i);
    SessionCamera s;
    s.name = c["name"].string();
    if (const std::string why = check_camera_name(s.name); !why.empty()) c["name"].fail(why);
    s.index = c["index"].string();  // path relative to the session
    s.depth_mode = read_mode(c["depth_mode"]);
    s.color_mode = read_mode(c["color_mode"]);
    s.depth_unit_mm = c["depth_unit_mm"].positive();
    s.depth_intrinsics = read_intrinsics(c["depth_intrinsics"]);
    if (s.depth_intrinsics.width <= 0 || s.depth_intrinsics.height <= 0) {
      c["depth_intrinsics"].fail("must have a positive width and height");
    }
    s.color_intrinsics = read_intrinsics(c["color_intrinsics"]);
    s.depth_to_color = read_pose(c["depth_to_color"]);
    s.camera_to_cell = read_pose(c["camera_to_cell"]);
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
      // A last line without its newline is the record a crash tore while the recorder wrote it.
      if (in.eof()) break;
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
