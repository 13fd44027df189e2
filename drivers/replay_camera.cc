#include "drivers/replay_camera.h"

#include <sstream>
#include <thread>

#include <fmt/format.h>

#include "drivers/pnm_image.h"

namespace drivers {

DriverResult ReplayDepthCamera::configure(const CameraConfig& config) {
  if (active_) return DriverResult::failure("replay camera: configure() while active; deactivate first");
  const std::string who = fmt::format("replay camera '{}'", config.name);
  const auto hash = config.uri.find('#');
  if (hash == std::string::npos || hash == 0) {
    return DriverResult::failure(who + ": uri must be '<session dir>#<camera name>[?pace=fast&loop=1&rebase=1]', got '" +
                                 config.uri + "'");
  }
  const std::filesystem::path dir = config.uri.substr(0, hash);
  std::string name = config.uri.substr(hash + 1);
  fast_ = loop_ = rebase_ = live_ = false;
  if (const auto q = name.find('?'); q != std::string::npos) {
    std::istringstream options(name.substr(q + 1));
    name.resize(q);
    for (std::string opt; std::getline(options, opt, '&');) {
      if (opt == "pace=fast") fast_ = true;
      else if (opt == "pace=recorded") fast_ = false;
      else if (opt == "loop=1" || opt == "loop=0") loop_ = opt == "loop=1";
      else if (opt == "rebase=1" || opt == "rebase=0") rebase_ = opt == "rebase=1";
      else if (opt == "live=1" || opt == "live=0") live_ = opt == "live=1";
      else return DriverResult::failure(fmt::format("{}: unknown uri option '{}'; expected pace=recorded|fast, loop=0|1, rebase=0|1, live=0|1", who, opt));
    }
  }
  try {
    const auto cameras = read_session(dir);
    const SessionCamera* found = nullptr;
    std::string names;
    for (const auto& c : cameras) {
      if (c.name == name) found = &c;
      names += (names.empty() ? "" : ", ") + c.name;
    }
    if (!found) {
      return DriverResult::failure(fmt::format("{}: {} has no camera '{}' (it has: {})", who,
                                               (dir / "session.json").string(), name, names));
    }
    camera_ = *found;
    index_ = read_session_index(dir / camera_.index);
    folder_ = (dir / camera_.index).parent_path();
    int line = 0;
    for (const auto& e : index_) {
      ++line;
      for (const std::string* file : {&e.depth_file, &e.color_file}) {
        if (!file->empty() && !std::filesystem::exists(folder_ / *file)) {
          return DriverResult::failure(fmt::format("{}: {}: frame {} (entry {}): missing file {}", who,
                                                   (dir / camera_.index).string(), e.sequence, line,
                                                   (folder_ / *file).string()));
        }
      }
    }
  } catch (const std::exception& e) {
    return DriverResult::failure(who + ": " + e.what());
  }
  if (index_.empty()) return DriverResult::failure(fmt::format("{}: {} holds no frames", who, (dir / camera_.index).string()));
  config_ = config;
  if (config_.name.empty()) config_.name = camera_.name;
  configured_ = true;
  health_ = {};
  health_.state = CameraState::kConfigured;
  return DriverResult::success();
}

DriverResult ReplayDepthCamera::activate() {
  if (!configured_) return DriverResult::failure("replay camera: activate() before configure()");
  next_ = 0;
  have_last_ = false;
  pass_sequence_ = 0;
  pass_device_us_ = 0;
  {
    // One pass of a loop (live=1): the recorded span plus one mean frame period (host clock, us).
    const std::int64_t span = index_.back().host_time_us - index_.front().host_time_us;
    const auto n = static_cast<std::int64_t>(index_.size());
    pass_host_us_ = span + (n > 1 ? span / (n - 1) : 33333);
  }
  start_ = std::chrono::steady_clock::now();
  start_us_ = host_clock_us();
  offset_us_ = index_.front().host_time_us;
  active_ = true;
  health_.state = CameraState::kActive;
  health_.message.clear();
  return DriverResult::success();
}

DriverResult ReplayDepthCamera::deactivate() {
  active_ = false;
  if (configured_) health_.state = CameraState::kConfigured;
  return DriverResult::success();
}

bool ReplayDepthCamera::load(std::size_t i, DepthFrame& f) {
  const SessionIndexEntry& e = index_[i];
  try {
    f.depth_mm = read_pgm16(folder_ / e.depth_file, camera_.depth_intrinsics.width, camera_.depth_intrinsics.height);
    if (e.color_file.empty()) {
      f.rgb.clear();
    } else {
      f.rgb = read_ppm8(folder_ / e.color_file, camera_.color_intrinsics.width, camera_.color_intrinsics.height);
    }
  } catch (const std::exception& ex) {
    health_.state = CameraState::kDegraded;
    health_.message = std::string("corrupt recorded frame skipped: ") + ex.what();
    return false;
  }
  f.camera = config_.name;
  f.sequence = e.sequence + pass_sequence_;
  f.device_time_us = e.device_time_us + pass_device_us_;
  f.host_time_us = rebase_ ? start_us_ + (e.host_time_us - offset_us_) : e.host_time_us;
  f.depth_intrinsics = camera_.depth_intrinsics;
  f.color_intrinsics = e.color_file.empty() ? Intrinsics{} : camera_.color_intrinsics;
  f.depth_to_color = camera_.depth_to_color;
  f.camera_to_cell = config_.camera_to_cell.matrix() == Eigen::Matrix4d::Identity() ? camera_.camera_to_cell
                                                                                     : config_.camera_to_cell;
  return true;
}

std::int64_t ReplayDepthCamera::pass_device_us() const {
  const std::int64_t span = index_.back().device_time_us - index_.front().device_time_us;
  const auto n = static_cast<std::int64_t>(index_.size());
  return span + (n > 1 ? span / (n - 1) : 33333);
}

ReadStatus ReplayDepthCamera::read(DepthFrame& frame) {
  if (!active_) return ReadStatus::kNotActive;
  const auto timeout = config_.read_timeout;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  bool skipped = false;
  std::size_t corrupt_in_a_row = 0;
  for (;;) {
    if (next_ >= index_.size()) {
      if (!loop_) {
        // The recording has ended: like a camera that stopped sending, wait (when paced) and time out.
        if (!fast_) std::this_thread::sleep_until(deadline);
        ++health_.timeouts;
        health_.state = CameraState::kDegraded;
        health_.message = fmt::format("end of recording ({} frames)", index_.size());
        return ReadStatus::kTimeout;
      }
      next_ = 0;
      if (live_) {
        // live=1: the next pass follows the last on schedule (one frame period after its last
        // frame) and continues its sequence and device clock, so a frame monitor sees one
        // unbroken stream; passes wholly in the past are skipped, as a live camera keeps running.
        const auto now = std::chrono::steady_clock::now();
        do {
          start_ += std::chrono::microseconds(pass_host_us_);
          start_us_ += pass_host_us_;
          pass_sequence_ += index_.back().sequence + 1 - index_.front().sequence;
          pass_device_us_ += pass_device_us();
        } while (!fast_ && start_ + std::chrono::microseconds(pass_host_us_) <= now);
      } else {
        // The next pass starts where the last one ended.
        start_ = std::chrono::steady_clock::now();
        start_us_ = host_clock_us();
        have_last_ = false;
      }
    }
    if (!fast_) {
      const auto due_at = [&](std::size_t k) {
        return start_ + std::chrono::microseconds(index_[k].host_time_us - offset_us_);
      };
      if (due_at(next_) > deadline) {
        std::this_thread::sleep_until(deadline);
        ++health_.timeouts;
        return ReadStatus::kTimeout;
      }
      std::this_thread::sleep_until(due_at(next_));
      if (live_) {
        // live=1: a late reader gets the newest frame already due, as from a live camera whose
        // driver overwrote the older buffers (the skipped ones show as a sequence gap = dropped).
        const auto now = std::chrono::steady_clock::now();
        while (next_ + 1 < index_.size() && due_at(next_ + 1) <= now) ++next_;
        if (loop_ && next_ + 1 == index_.size() && start_ + std::chrono::microseconds(pass_host_us_) <= now) {
          next_ = index_.size();  // the next pass has begun: continue there
          continue;
        }
      }
    }
    const std::size_t i = next_++;
    if (load(i, frame)) break;
    skipped = true;  // health_.message names the file
    // With loop=1 a recording whose every frame is corrupt would be read round and round.
    if (++corrupt_in_a_row >= index_.size()) {
      ++health_.timeouts;
      health_.message = fmt::format("every recorded frame is corrupt; the last: {}", health_.message);
      return ReadStatus::kCorrupt;
    }
  }
  if (have_last_ && frame.sequence > last_sequence_ + 1) health_.dropped += frame.sequence - last_sequence_ - 1;
  have_last_ = true;
  last_sequence_ = frame.sequence;
  ++health_.frames;
  health_.last_frame_host_time_us = frame.host_time_us;
  health_.state = skipped ? CameraState::kDegraded : CameraState::kActive;
  if (!skipped) health_.message.clear();
  return ReadStatus::kFrame;
}

}  // namespace drivers
