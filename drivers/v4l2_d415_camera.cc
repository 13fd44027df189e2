#include "drivers/v4l2_d415_camera.h"

#include <linux/videodev2.h>

#include <algorithm>
#include <cmath>

#include "drivers/yuyv_color.h"

namespace drivers {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::chrono::milliseconds kFirstBackoff{100}, kMaxBackoff{2000};

// Read deadlines are on the wall: the device's driver waits in wall time whatever clock the
// process runs on (a simulated one may stand still while this process holds it).
std::int64_t steady_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

V4l2D415Uri parse_v4l2_d415_uri(const std::string& uri, std::string& error) {
  V4l2D415Uri out;
  error.clear();
  std::size_t pos = 0;
  while (pos <= uri.size()) {
    const std::size_t comma = std::min(uri.find(',', pos), uri.size());
    const std::string item = uri.substr(pos, comma - pos);
    const std::size_t eq = item.find('=');
    const std::string key = item.substr(0, eq), value = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (eq == std::string::npos || value.empty() || (key != "depth" && key != "color")) {
      error = "v4l2 uri \"" + uri + "\": expected depth=/dev/videoN[,color=/dev/videoM], got \"" + item + "\"";
      return {};
    }
    (key == "depth" ? out.depth_path : out.color_path) = value;
    pos = comma + 1;
  }
  if (out.depth_path.empty()) error = "v4l2 uri \"" + uri + "\": missing depth=/dev/videoN";
  return out;
}

V4l2D415Camera::V4l2D415Camera(std::shared_ptr<V4l2Io> io) : io_(std::move(io)), depth_(*io_), color_(*io_) {}

V4l2D415Camera::~V4l2D415Camera() {
  depth_.close();
  color_.close();
}

DriverResult V4l2D415Camera::configure(const CameraConfig& config) {
  std::string error;
  V4l2D415Uri uri = parse_v4l2_d415_uri(config.uri, error);
  if (!error.empty()) return DriverResult::failure(config.name + ": " + error);
  if (!config.serial.empty() && uri.depth_path.find(config.serial) == std::string::npos)
    return DriverResult::failure(config.name + ": serial " + config.serial +
                                 " cannot be read over V4L2; name the device by its /dev/v4l/by-id/ path,"
                                 " which contains the serial (got " + uri.depth_path + ")");
  if (config.depth_intrinsics.width == 0)
    return DriverResult::failure(config.name + ": depth_intrinsics are missing (V4L2 cannot read a D415's "
                                 "calibration; copy it from the camera's calibration into the config)");
  if (!uri.color_path.empty() && config.color_intrinsics.width == 0)
    return DriverResult::failure(config.name + ": uri names a colour node but color_intrinsics are missing");
  config_ = config;
  uri_ = uri;
  health_ = CameraHealth{};
  active_ = lost_ = false;  // a new configuration starts over (open_nodes closes the old nodes)
  DriverResult opened = open_nodes();
  if (!opened.ok) return DriverResult::failure(config.name + ": " + opened.message);
  health_.state = CameraState::kConfigured;
  return DriverResult::success();
}

DriverResult V4l2D415Camera::open_nodes() {
  DriverResult r = depth_.open({uri_.depth_path, V4L2_PIX_FMT_Z16, config_.depth_mode.width,
                                config_.depth_mode.height, config_.depth_mode.fps, 2});
  if (r.ok && !uri_.color_path.empty())
    r = color_.open({uri_.color_path, V4L2_PIX_FMT_YUYV, config_.color_mode.width,
                     config_.color_mode.height, config_.color_mode.fps, 2});
  if (!r.ok) {
    depth_.close();
    color_.close();
  }
  have_color_pending_ = false;
  return r;
}

DriverResult V4l2D415Camera::start_nodes() {
  DriverResult r = depth_.start();
  if (r.ok && color_.is_open()) r = color_.start();
  return r;
}

DriverResult V4l2D415Camera::activate() {
  if (health_.state == CameraState::kUnconfigured) return DriverResult::failure("activate() before configure()");
  if (active_) return DriverResult::success();
  if (!depth_.is_open()) {  // deactivated before: open again
    DriverResult opened = open_nodes();
    if (!opened.ok) return DriverResult::failure(config_.name + ": " + opened.message);
  }
  DriverResult r = start_nodes();
  if (!r.ok) return DriverResult::failure(config_.name + ": " + r.message);
  active_ = true;
  lost_ = false;
  health_.state = CameraState::kActive;
  health_.message.clear();
  return DriverResult::success();
}

DriverResult V4l2D415Camera::deactivate() {
  depth_.close();
  color_.close();
  active_ = false;
  lost_ = false;
  if (health_.state != CameraState::kUnconfigured) health_.state = CameraState::kConfigured;
  return DriverResult::success();
}

ReadStatus V4l2D415Camera::lose(const std::string& why) {
  depth_.close();
  color_.close();
  lost_ = true;
  backoff_ = std::chrono::milliseconds{0};  // first reopen attempt on the next read
  next_reopen_ = Clock::now();
  health_.state = CameraState::kLost;
  health_.message = config_.name + " lost: " + why;
  return ReadStatus::kLost;
}

bool V4l2D415Camera::reopen_due() {
  if (Clock::now() < next_reopen_) return false;
  ++health_.reopen_attempts;
  DriverResult r = open_nodes();
  if (r.ok) r = start_nodes();
  if (!r.ok) {
    depth_.close();
    color_.close();
    backoff_ = std::clamp(backoff_ * 2, kFirstBackoff, kMaxBackoff);
    next_reopen_ = Clock::now() + backoff_;
    health_.message = config_.name + " lost; reopen attempt " + std::to_string(health_.reopen_attempts) +
                      " failed: " + r.message;
    return false;
  }
  ++health_.reopened;
  lost_ = false;
  health_.state = CameraState::kActive;
  health_.message.clear();
  return true;
}

ReadStatus V4l2D415Camera::read(DepthFrame& frame) {
  if (!active_) return ReadStatus::kNotActive;
  if (lost_ && !reopen_due()) return ReadStatus::kLost;
  const std::int64_t deadline_ms = steady_ms() + config_.read_timeout.count();
  switch (depth_.next(static_cast<int>(config_.read_timeout.count()), depth_image_)) {
    case CaptureStatus::kTimeout: ++health_.timeouts; return ReadStatus::kTimeout;
    case CaptureStatus::kLost: return lose(depth_.error());
    case CaptureStatus::kFrame: break;
  }
  frame.camera = config_.name;
  frame.sequence = depth_image_.sequence;
  frame.device_time_us = depth_image_.timestamp_us;
  frame.host_time_us = host_clock_us();
  frame.depth_intrinsics = config_.depth_intrinsics;
  frame.depth_to_color = config_.depth_to_color;
  frame.camera_to_cell = config_.camera_to_cell;
  const std::size_t pixels = depth_image_.data.size() / 2;
  frame.depth_mm.resize(pixels);
  const auto* raw = reinterpret_cast<const std::uint16_t*>(depth_image_.data.data());
  if (config_.depth_unit_mm == 1.0) {
    std::copy(raw, raw + pixels, frame.depth_mm.begin());
  } else {
    for (std::size_t i = 0; i < pixels; ++i)
      frame.depth_mm[i] = static_cast<std::uint16_t>(std::min(65535.0, std::round(raw[i] * config_.depth_unit_mm)));
  }
  frame.color_intrinsics = Intrinsics{};
  frame.rgb.clear();
  if (color_.is_open() && !pair_color(frame.device_time_us, deadline_ms, frame)) return lose(color_.error());
  ++health_.frames;
  health_.last_frame_host_time_us = frame.host_time_us;
  if (depth_image_.driver_error) return ReadStatus::kCorrupt;  // uvcvideo flagged the buffer
  // uvcvideo stamps buffers with CLOCK_MONOTONIC, the host's steady clock: the age is exact.
  if (depth_image_.monotonic_clock &&
      frame.host_time_us - frame.device_time_us > std::chrono::microseconds(config_.stale_after).count()) {
    ++health_.stale;
    return ReadStatus::kStale;
  }
  return ReadStatus::kFrame;
}

bool V4l2D415Camera::pair_color(std::int64_t depth_time_us, std::int64_t deadline_ms, DepthFrame& frame) {
  const std::int64_t period_us = 1000000 / std::max(1, config_.color_mode.fps);
  auto distance = [&](const CapturedImage& c) { return std::llabs(c.timestamp_us - depth_time_us); };
  // Candidates come in time order: the one carried over from the last read, then every frame
  // already waiting. Keep the nearest; the first one farther away than that (it is past the
  // depth time) is carried over to the next read. If the best is still older than half a period,
  // the matching frame is probably in flight: wait for it once, bounded by the read deadline.
  have_color_image_ = false;
  bool waited = false;
  for (;;) {
    if (have_color_pending_) {
      std::swap(color_scratch_, color_pending_);
      have_color_pending_ = false;
    } else {
      const bool need_wait = !have_color_image_ || color_image_.timestamp_us < depth_time_us - period_us / 2;
      int wait_ms = 0;
      if (need_wait && !waited) {
        wait_ms = static_cast<int>(std::clamp<std::int64_t>(
            std::min(deadline_ms - steady_ms(), period_us / 1000 + 1), 0, 1000));
        waited = true;
      }
      const CaptureStatus s = color_.next(wait_ms, color_scratch_);
      if (s == CaptureStatus::kLost) return false;
      if (s == CaptureStatus::kTimeout) break;
    }
    if (have_color_image_ && distance(color_scratch_) > distance(color_image_)) {
      std::swap(color_pending_, color_scratch_);
      have_color_pending_ = true;
      break;
    }
    std::swap(color_image_, color_scratch_);
    have_color_image_ = true;
  }
  if (!have_color_image_ || distance(color_image_) > period_us || color_image_.driver_error) return true;
  const int w = config_.color_mode.width, h = config_.color_mode.height;
  if (color_image_.data.size() != static_cast<std::size_t>(w) * h * 2) return true;  // short frame
  yuyv_to_rgb(color_image_.data.data(), w, h, frame.rgb);
  frame.color_intrinsics = config_.color_intrinsics;
  return true;
}

}  // namespace drivers
