#include "drivers/session_recorder.h"

#include <stdexcept>

#include <fmt/format.h>

#include "common/durable_file.h"
#include "drivers/pnm_image.h"

namespace drivers {

SessionRecorder::SessionRecorder(std::filesystem::path dir) : dir_(std::move(dir)) {
  try {
    prepreg::create_directories_durably(dir_);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("cannot create the session directory: {}", e.what()));
  }
  if (std::filesystem::exists(dir_ / "session.json")) {
    throw std::runtime_error(fmt::format("{}: already holds a recorded session (session.json); choose a new directory",
                                         dir_.string()));
  }
}

void SessionRecorder::describe(const CameraConfig& config) { described_[config.name] = config; }

DriverResult SessionRecorder::start_track(const DepthFrame& f) {
  if (const std::string why = check_camera_name(f.camera); !why.empty()) return DriverResult::failure(why);
  const std::filesystem::path folder = dir_ / f.camera;
  try {
    prepreg::create_directories_durably(folder);
  } catch (const std::exception& e) {
    return DriverResult::failure(e.what());
  }
  Track t;
  SessionCamera& c = t.camera;
  c.name = f.camera;
  c.index = f.camera + "/index.txt";
  c.depth_intrinsics = f.depth_intrinsics;
  c.color_intrinsics = f.color_intrinsics;
  c.depth_to_color = f.depth_to_color;
  c.camera_to_cell = f.camera_to_cell;
  c.depth_mode = {f.depth_intrinsics.width, f.depth_intrinsics.height, 0};
  c.color_mode = {f.color_intrinsics.width, f.color_intrinsics.height, 0};
  if (const auto it = described_.find(f.camera); it != described_.end()) {
    // The frame rate only if the described mode is the one streaming (a replayed camera, for
    // one, ignores the modes it is configured with).
    const auto same_size = [](const StreamMode& m, const Intrinsics& k) { return m.width == k.width && m.height == k.height; };
    if (same_size(it->second.depth_mode, f.depth_intrinsics)) c.depth_mode.fps = it->second.depth_mode.fps;
    if (same_size(it->second.color_mode, f.color_intrinsics)) c.color_mode.fps = it->second.color_mode.fps;
    c.depth_unit_mm = it->second.depth_unit_mm;
  }
  try {
    t.index = std::make_unique<prepreg::AppendJournal>(dir_ / c.index);
    t.index->append(fmt::format("# {} v{} index: sequence device_time_us host_time_us depth_file color_file\n",
                                kSessionFormat, kSessionVersion));
  } catch (const std::exception& e) {
    return DriverResult::failure(e.what());
  }
  tracks_.emplace(f.camera, std::move(t));
  order_.push_back(f.camera);
  std::vector<SessionCamera> cams;
  for (const auto& name : order_) cams.push_back(tracks_.at(name).camera);
  if (const std::string err = write_session(dir_, cams); !err.empty()) return DriverResult::failure(err);
  return DriverResult::success();
}

DriverResult SessionRecorder::append(const DepthFrame& f) {
  try {
    if (!tracks_.count(f.camera)) {
      if (const auto r = start_track(f); !r.ok) return r;
    }
    Track& t = tracks_.at(f.camera);
    const SessionCamera& c = t.camera;
    const auto same = [](const Intrinsics& a, const Intrinsics& b) {
      return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx &&
             a.cy == b.cy && a.k1 == b.k1 && a.k2 == b.k2 && a.p1 == b.p1 && a.p2 == b.p2 && a.k3 == b.k3;
    };
    if (!same(f.depth_intrinsics, c.depth_intrinsics) || !same(f.color_intrinsics, c.color_intrinsics) ||
        f.depth_to_color.matrix() != c.depth_to_color.matrix() || f.camera_to_cell.matrix() != c.camera_to_cell.matrix()) {
      return DriverResult::failure(fmt::format(
          "camera '{}' frame {}: intrinsics or extrinsics changed during the session (a session stores them once)",
          f.camera, f.sequence));
    }
    SessionIndexEntry e{f.sequence, f.device_time_us, f.host_time_us, fmt::format("depth_{:06d}.pgm", t.frames), ""};
    const std::filesystem::path folder = dir_ / f.camera;
    std::string err = write_pgm16(folder / e.depth_file, c.depth_intrinsics.width, c.depth_intrinsics.height, f.depth_mm);
    if (err.empty() && c.color_intrinsics.width > 0) {
      e.color_file = fmt::format("color_{:06d}.ppm", t.frames);
      err = write_ppm8(folder / e.color_file, c.color_intrinsics.width, c.color_intrinsics.height, f.rgb);
    }
    if (!err.empty()) return DriverResult::failure(err);
    t.index->append(format_index_line(e) + '\n');  // throws naming the index; reported below
    ++t.frames;
    return DriverResult::success();
  } catch (const std::exception& e) {  // allocation or filesystem errors: report, do not throw
    return DriverResult::failure(fmt::format("recording camera '{}': {}", f.camera, e.what()));
  }
}

std::uint64_t SessionRecorder::frames(const std::string& camera) const {
  const auto it = tracks_.find(camera);
  return it == tracks_.end() ? 0 : it->second.frames;
}

std::uint64_t record_frames(DepthCamera& camera, SessionRecorder& recorder, std::uint64_t frames,
                            std::uint64_t max_reads, std::string* error) {
  DepthFrame f;
  std::uint64_t recorded = 0;
  for (std::uint64_t i = 0; i < max_reads && recorded < frames; ++i) {
    const ReadStatus s = camera.read(f);
    if (s == ReadStatus::kLost || s == ReadStatus::kNotActive) {
      if (error) *error = fmt::format("camera read returned {}", to_string(s));
      break;
    }
    if (s == ReadStatus::kTimeout) continue;
    const DriverResult r = recorder.append(f);
    if (!r.ok) {
      if (error) *error = r.message;
      break;
    }
    ++recorded;
  }
  return recorded;
}

}  // namespace drivers
