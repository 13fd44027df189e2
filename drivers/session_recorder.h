#pragma once
// Records frames from any DepthCamera into a session directory (format: camera_session.h).
// Frame files and index lines are written as frames arrive, and session.json is rewritten whenever
// a camera is added, each durably (common/durable_file.h, common/append_journal.h): a frame file is
// on the disk before its index line is written and flushed, so a recording cut short by a crash
// or a power cut is still readable up to its last complete frame. That costs a few fsyncs per
// frame; on a slow disk the recorder records fewer frames than the camera delivers.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "common/append_journal.h"
#include "drivers/camera_session.h"
#include "drivers/depth_camera.h"

namespace drivers {

class SessionRecorder {
 public:
  // Creates `dir` (and parents). Throws std::runtime_error naming the directory if it cannot be
  // created or already holds a session.json (a recording is never overwritten).
  explicit SessionRecorder(std::filesystem::path dir);

  // Optional, before a camera's first frame: its frame rates and depth unit for session.json.
  // Modes are always the frame's image sizes; fps is taken from the config where its mode has
  // that size, else 0 (unknown); unit 1 mm if not described.
  void describe(const CameraConfig& config);

  // Appends one frame (camera = frame.camera). Never throws: I/O errors and frames whose
  // intrinsics or extrinsics differ from the camera's first frame are reported in the result.
  DriverResult append(const DepthFrame& frame);

  std::uint64_t frames(const std::string& camera) const;
  const std::filesystem::path& directory() const { return dir_; }

 private:
  struct Track {
    SessionCamera camera;
    std::unique_ptr<prepreg::AppendJournal> index;
    std::uint64_t frames = 0;
  };
  DriverResult start_track(const DepthFrame& frame);

  std::filesystem::path dir_;
  std::map<std::string, CameraConfig> described_;
  std::map<std::string, Track> tracks_;
  std::vector<std::string> order_;  // cameras in session.json in order of first frame
};

// Reads from an active camera until `frames` frames (kFrame, kStale or kFrozen) were recorded or
// `max_reads` reads were made; returns the number recorded. Stops early on kLost/kNotActive or
// a recorder error (put in `error` if given).
std::uint64_t record_frames(DepthCamera& camera, SessionRecorder& recorder, std::uint64_t frames,
                            std::uint64_t max_reads, std::string* error = nullptr);

}  // namespace drivers
