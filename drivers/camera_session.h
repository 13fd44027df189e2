#pragma once
// The on-disk format of a recorded camera session (format "prepreg_camera_session", version 1),
// so a run on a real cell can be replayed in CI and in the tracker benchmark:
//
//   <session>/session.json   {"format": "prepreg_camera_session", "version": 1,
//                             "cameras": [{"name": "cam_left", "index": "cam_left/index.txt",
//                               "depth_mode": {"width": 848, "height": 480, "fps": 30},
//                               "color_mode": {...}, "depth_unit_mm": 1.0,
//                               "depth_intrinsics": {"width", "height", "fx", "fy", "cx", "cy",
//                                                    "k1", "k2", "p1", "p2", "k3"},
//                               "color_intrinsics": {... width 0 = no colour},
//                               "depth_to_color": [16 numbers, 4x4 row-major, m],
//                               "camera_to_cell": [16 numbers, 4x4 row-major, m]}, ...]}
//   <session>/<camera>/index.txt   '#' comment lines, then one line per frame:
//                             sequence device_time_us host_time_us depth_file color_file
//                             (file names relative to the camera folder; color_file "-" = none;
//                             a last line without its newline that does not read as a frame is
//                             skipped: a crash tore it while it was being written)
//   <session>/<camera>/depth_<n>.pgm   16-bit binary PGM, raw depth counts (0 = invalid)
//   <session>/<camera>/color_<n>.ppm   8-bit binary PPM, RGB
//
// Numbers in session.json are written with full double precision, so a replay reproduces the
// recorded frames bit for bit. Intrinsics and extrinsics are per camera (constant over a session).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"

namespace drivers {

inline constexpr const char* kSessionFormat = "prepreg_camera_session";
inline constexpr int kSessionVersion = 1;

struct SessionCamera {
  std::string name;   // also the folder name: letters, digits, '_', '-', '.'
  std::string index;  // relative to the session directory
  StreamMode depth_mode, color_mode;
  double depth_unit_mm = 1.0;
  Intrinsics depth_intrinsics, color_intrinsics;
  Eigen::Isometry3d depth_to_color = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_to_cell = Eigen::Isometry3d::Identity();
};

struct SessionIndexEntry {
  std::uint64_t sequence = 0;
  std::int64_t device_time_us = 0, host_time_us = 0;
  std::string depth_file, color_file;  // relative to the camera folder; color "" = none
};

// "" if `name` can be a camera folder name, else why not.
std::string check_camera_name(const std::string& name);

// session.json of `dir`. write_session returns "" or an error naming the file; read_session
// throws std::runtime_error naming the file when it cannot be opened or parsed, and
// std::invalid_argument naming the file and the field ("cameras[1].fx") and what was expected.
std::string write_session(const std::filesystem::path& dir, const std::vector<SessionCamera>& cameras);
std::vector<SessionCamera> read_session(const std::filesystem::path& dir);

// One index line (no newline).
std::string format_index_line(const SessionIndexEntry& entry);
// Reads an index file; throws std::runtime_error "<file>:<line>: ..." saying what was expected.
std::vector<SessionIndexEntry> read_session_index(const std::filesystem::path& index_file);

}  // namespace drivers
