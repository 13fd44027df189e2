#include "drivers/openni2_camera.h"

#include <OpenNI.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "drivers/openni2_frames.h"
#include "drivers/openni2_modes.h"
#include "drivers/openni2_runtime.h"

namespace drivers {
namespace {

using Clock = std::chrono::steady_clock;

// "path.oni?speed=X" -> path and speed; any other URI is passed to OpenNI2 unchanged.
struct ParsedUri {
  std::string device;
  float playback_speed = -1.0f;  // OpenNI2 "manual": a frame per read, as fast as read
};

ParsedUri parse_uri(const std::string& uri) {
  ParsedUri parsed{uri};
  const auto query = uri.find("?speed=");
  if (query != std::string::npos) {
    parsed.device = uri.substr(0, query);
    parsed.playback_speed = std::strtof(uri.c_str() + query + 7, nullptr);
  }
  return parsed;
}

// Drivers' stream threads can outlive stop(): close_device() waits this long after stopping the
// streams before it destroys them.
// - Debian's OniFile player thread walks its stream list without a lock and spins while a stream
//   is started (e.g. at the end of a recording), so destroying a stream under it crashed in about
//   1 of 50 closes here; with every stream stopped it idles in 10 ms sleeps (30 ms waited).
// - Debian's DummyDevice stops a stream by setting a flag its thread reads after each frame's
//   sleep (33 ms at 30 fps), without joining the thread, and destroy() frees the stream under it:
//   the Dummy device's openni2 test crashed (SIGSEGV in libDummyDevice) in 3 of 30 runs of the
//   openni2 tests at ctest -j4. Three frame periods are waited for every device,
//   except when a lost device is reopened: its streams died with it, and a cyclic reader must
//   not block there.
constexpr std::chrono::milliseconds kStopSettle{100};
constexpr std::chrono::milliseconds kPlaybackStopSettle{30};

class OpenNI2Camera final : public DepthCamera, private openni::OpenNI::DeviceDisconnectedListener {
 public:
  ~OpenNI2Camera() override {
    close_device();
    if (listening_) openni::OpenNI::removeDeviceDisconnectedListener(this);
  }

  DriverResult configure(const CameraConfig& config) override {
    if (active_) return DriverResult::failure(config_.name + ": configure() while active");
    close_device();
    config_ = config;
    uri_ = parse_uri(config.uri);
    if (uri_.device.empty()) {
      return fail_configure("uri is empty (expected an OpenNI2 device URI, \"any\" or an .oni file)");
    }
    if (config.depth_mode.width <= 0 || config.depth_mode.height <= 0 || config.depth_mode.fps <= 0) {
      return fail_configure("depth_mode must have positive width, height and fps");
    }
    if (!runtime_) runtime_ = std::make_unique<OpenNI2Runtime>();
    if (!runtime_->ok()) return fail_configure(runtime_->message());
    if (!listening_) {
      listening_ = openni::OpenNI::addDeviceDisconnectedListener(this) == openni::STATUS_OK;
    }
    DriverResult opened = open_device();
    if (!opened.ok) {
      close_device();
      return fail_configure(opened.message);
    }
    set_state(CameraState::kConfigured, "");
    return DriverResult::success();
  }

  DriverResult activate() override {
    if (!device_.isValid()) return DriverResult::failure(config_.name + ": activate() before configure()");
    DriverResult started = start_streams();
    if (!started.ok) return DriverResult::failure(config_.name + ": " + started.message);
    active_ = true;
    set_state(CameraState::kActive, "");
    return DriverResult::success();
  }

  ReadStatus read(DepthFrame& frame) override {
    if (!active_) return ReadStatus::kNotActive;
    if (disconnected_ && !lost_) mark_lost("OpenNI2 reported the device disconnected");
    if (lost_ && !try_reopen()) return ReadStatus::kLost;

    const auto deadline = Clock::now() + config_.read_timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      openni::VideoStream* streams[2] = {&depth_, &color_};
      int ready = -1;
      const openni::Status rc = openni::OpenNI::waitForAnyStream(
          streams, has_color_ ? 2 : 1, &ready, static_cast<int>(std::max<std::int64_t>(0, left.count())));
      if (disconnected_) return lose("OpenNI2 reported the device disconnected");
      if (rc == openni::STATUS_TIME_OUT) return timed_out();
      if (rc != openni::STATUS_OK) return lose("waiting for frames failed: " + openni2_error_text());
      if (ready == 1) {
        if (!read_color()) return lose("reading a colour frame failed: " + openni2_error_text());
        continue;
      }
      openni::VideoFrameRef ref;
      if (depth_.readFrame(&ref) != openni::STATUS_OK) {
        return lose("reading a depth frame failed: " + openni2_error_text());
      }
      return deliver(ref, frame, deadline);
    }
  }

  CameraHealth health() const override {
    std::lock_guard lock(health_mutex_);
    return health_;
  }

  DriverResult deactivate() override {
    if (active_) {
      depth_.stop();
      if (has_color_) color_.stop();
    }
    active_ = false;
    set_state(device_.isValid() ? CameraState::kConfigured : CameraState::kUnconfigured, "");
    return DriverResult::success();
  }

 private:
  void onDeviceDisconnected(const openni::DeviceInfo* info) override {
    std::lock_guard lock(uri_mutex_);
    if (info != nullptr && device_uri_ == info->getUri()) disconnected_ = true;
  }

  DriverResult fail_configure(const std::string& why) {
    set_state(CameraState::kUnconfigured, why);
    return DriverResult::failure(config_.name + ": " + why);
  }

  DriverResult open_device() {
    const bool any = uri_.device == "any";
    if (device_.open(any ? openni::ANY_DEVICE : uri_.device.c_str()) != openni::STATUS_OK) {
      return DriverResult::failure(
          fmt::format("cannot open OpenNI2 device \"{}\": {}", uri_.device, openni2_error_text()));
    }
    {
      std::lock_guard lock(uri_mutex_);
      device_uri_ = device_.getDeviceInfo().getUri();
      disconnected_ = false;
    }
    if (!config_.serial.empty()) {
      char serial[ONI_MAX_STR] = {};
      int size = sizeof(serial);
      if (device_.getProperty(ONI_DEVICE_PROPERTY_SERIAL_NUMBER, serial, &size) != openni::STATUS_OK) {
        return DriverResult::failure(
            fmt::format("device \"{}\" does not report a serial number (config expects \"{}\"): {}",
                        device_uri_, config_.serial, openni2_error_text()));
      }
      serial[sizeof(serial) - 1] = '\0';
      if (config_.serial != serial) {
        return DriverResult::failure(fmt::format(
            "serial number mismatch on device \"{}\": the device reports \"{}\", the config expects \"{}\"",
            device_uri_, serial, config_.serial));
      }
    }
    if (!device_.hasSensor(openni::SENSOR_DEPTH)) {
      return DriverResult::failure(fmt::format("device \"{}\" has no depth sensor", device_uri_));
    }
    if (depth_.create(device_, openni::SENSOR_DEPTH) != openni::STATUS_OK) {
      return DriverResult::failure("cannot create the depth stream: " + openni2_error_text());
    }
    DriverResult mode =
        select_openni2_mode(depth_, config_.depth_mode, openni::PIXEL_FORMAT_DEPTH_1_MM, "depth");
    if (!mode.ok) return mode;
    if (depth_.getMirroringEnabled()) depth_.setMirroringEnabled(false);
    has_color_ = device_.hasSensor(openni::SENSOR_COLOR);
    if (has_color_) {
      if (color_.create(device_, openni::SENSOR_COLOR) != openni::STATUS_OK) {
        return DriverResult::failure("cannot create the colour stream: " + openni2_error_text());
      }
      mode = select_openni2_mode(color_, config_.color_mode, openni::PIXEL_FORMAT_RGB888, "colour");
      if (!mode.ok) return mode;
      if (color_.getMirroringEnabled()) color_.setMirroringEnabled(false);
    }
    if (device_.getImageRegistrationMode() != openni::IMAGE_REGISTRATION_OFF &&
        device_.setImageRegistrationMode(openni::IMAGE_REGISTRATION_OFF) != openni::STATUS_OK) {
      return DriverResult::failure("cannot turn image registration off: " + openni2_error_text());
    }
    recording_frames_ = 0;
    if (openni::PlaybackControl* playback = device_.getPlaybackControl()) {
      if (playback->setSpeed(uri_.playback_speed) != openni::STATUS_OK ||
          playback->setRepeatEnabled(false) != openni::STATUS_OK) {
        return DriverResult::failure("cannot set playback speed/repeat: " + openni2_error_text());
      }
      recording_frames_ = playback->getNumberOfFrames(depth_);
    }
    last_sequence_ = 0;
    colors_.clear();
    return DriverResult::success();
  }

  DriverResult start_streams() {
    if (depth_.start() != openni::STATUS_OK) {
      return DriverResult::failure("cannot start the depth stream: " + openni2_error_text());
    }
    if (has_color_ && color_.start() != openni::STATUS_OK) {
      return DriverResult::failure("cannot start the colour stream: " + openni2_error_text());
    }
    return DriverResult::success();
  }

  enum class Settle { kDriverThreads, kPlaybackOnly };
  void close_device(Settle settle = Settle::kDriverThreads) {
    // Stop both streams before destroying either, and let the drivers' threads see it (kStopSettle).
    const bool playback = device_.isValid() && device_.isFile();
    const bool streams = depth_.isValid() || color_.isValid();
    if (depth_.isValid()) depth_.stop();
    if (color_.isValid()) color_.stop();
    if (streams && settle == Settle::kDriverThreads) {
      std::this_thread::sleep_for(kStopSettle);
    } else if (playback) {
      std::this_thread::sleep_for(kPlaybackStopSettle);
    }
    if (depth_.isValid()) depth_.destroy();
    if (color_.isValid()) color_.destroy();
    if (device_.isValid()) device_.close();
    has_color_ = false;
  }

  void mark_lost(const std::string& why) {
    lost_ = true;
    last_reopen_attempt_ = Clock::now();  // give the device a read_timeout before the first try
    set_state(CameraState::kLost, why);
  }

  ReadStatus lose(const std::string& why) {
    mark_lost(why);
    return ReadStatus::kLost;
  }

  // Reopens at most once per read_timeout so a cyclic reader does not hammer a missing device.
  bool try_reopen() {
    const auto now = Clock::now();
    if (now - last_reopen_attempt_ < config_.read_timeout) return false;
    last_reopen_attempt_ = now;
    std::string lost_reason;
    {
      std::lock_guard lock(health_mutex_);
      ++health_.reopen_attempts;
      lost_reason = health_.message;
    }
    close_device(Settle::kPlaybackOnly);
    DriverResult result = open_device();
    if (result.ok) result = start_streams();
    if (!result.ok) {
      close_device(Settle::kPlaybackOnly);
      const auto cut = lost_reason.find("; reopen failed");
      if (cut != std::string::npos) lost_reason.resize(cut);
      set_state(CameraState::kLost, lost_reason + "; reopen failed: " + result.message);
      return false;
    }
    lost_ = false;
    {
      std::lock_guard lock(health_mutex_);
      ++health_.reopened;
    }
    set_state(CameraState::kActive, "");
    return true;
  }

  ReadStatus timed_out() {
    if (recording_frames_ > 0 && last_sequence_ >= static_cast<std::uint64_t>(recording_frames_)) {
      set_state(CameraState::kDegraded,
                fmt::format("end of recording {} after {} depth frames", uri_.device, recording_frames_));
      return ReadStatus::kTimeout;
    }
    std::lock_guard lock(health_mutex_);
    ++health_.timeouts;
    return ReadStatus::kTimeout;
  }

  Intrinsics stream_intrinsics(const openni::VideoStream& stream, const Intrinsics& configured, int width,
                               int height) const {
    if (configured.width == width && configured.height == height) return configured;
    return intrinsics_from_fov(width, height, stream.getHorizontalFieldOfView(),
                               stream.getVerticalFieldOfView());
  }

  bool read_color() {
    openni::VideoFrameRef ref;
    if (color_.readFrame(&ref) != openni::STATUS_OK) return false;
    ColorImage image;
    image.device_time_us = static_cast<std::int64_t>(ref.getTimestamp());
    image.intrinsics = stream_intrinsics(color_, config_.color_intrinsics, ref.getWidth(), ref.getHeight());
    copy_openni2_rgb(ref, image.rgb);
    colors_.add(std::move(image));
    return true;
  }

  // Reads colour until one is at least as new as the depth frame, so pairing sees the colour
  // taken with it. Waits at most one colour frame period (and never past the read deadline): a
  // colour frame that has not come by then is late, and the nearest older one is used.
  void catch_up_color(std::int64_t depth_time_us, Clock::time_point deadline) {
    if (!has_color_) return;
    const auto period = std::chrono::milliseconds(1000 / std::max(1, config_.color_mode.fps) + 1);
    deadline = std::min(deadline, Clock::now() + period);
    for (std::size_t i = 0; i < ColorHistory::kCapacity; ++i) {
      if (!colors_.empty() && colors_.newest_time_us() >= depth_time_us) return;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      openni::VideoStream* streams[1] = {&color_};
      int ready = -1;
      if (openni::OpenNI::waitForAnyStream(streams, 1, &ready,
                                           static_cast<int>(std::max<std::int64_t>(0, left.count()))) !=
          openni::STATUS_OK) {
        return;
      }
      if (!read_color()) return;
    }
  }

  ReadStatus deliver(const openni::VideoFrameRef& ref, DepthFrame& frame, Clock::time_point deadline) {
    const int width = ref.getWidth(), height = ref.getHeight();
    frame.camera = config_.name;
    frame.sequence = static_cast<std::uint64_t>(ref.getFrameIndex());
    frame.device_time_us = static_cast<std::int64_t>(ref.getTimestamp());
    frame.host_time_us = host_clock_us();
    frame.depth_intrinsics = stream_intrinsics(depth_, config_.depth_intrinsics, width, height);
    copy_openni2_depth(ref, frame.depth_mm);
    frame.depth_to_color = config_.depth_to_color;
    frame.camera_to_cell = config_.camera_to_cell;
    catch_up_color(frame.device_time_us, deadline);
    const ColorImage* best = colors_.nearest(frame.device_time_us);
    frame.color_intrinsics = best != nullptr ? best->intrinsics : Intrinsics{};
    frame.rgb = best != nullptr ? best->rgb : std::vector<std::uint8_t>{};
    last_sequence_ = frame.sequence;
    std::lock_guard lock(health_mutex_);
    ++health_.frames;
    health_.last_frame_host_time_us = frame.host_time_us;
    return ReadStatus::kFrame;
  }

  void set_state(CameraState state, const std::string& message) {
    std::lock_guard lock(health_mutex_);
    health_.state = state;
    health_.message = message;
  }

  CameraConfig config_;
  ParsedUri uri_;
  std::unique_ptr<OpenNI2Runtime> runtime_;  // declared before the OpenNI2 objects it outlives
  bool listening_ = false;
  openni::Device device_;
  openni::VideoStream depth_, color_;
  bool has_color_ = false;
  bool active_ = false;
  bool lost_ = false;
  Clock::time_point last_reopen_attempt_{};
  int recording_frames_ = 0;  // depth frames in the recording; 0 for a live device

  std::mutex uri_mutex_;  // device_uri_ is read by OpenNI2's disconnect callback thread
  std::string device_uri_;
  std::atomic<bool> disconnected_{false};

  ColorHistory colors_;
  // OpenNI2's frame index of the last depth frame (0 = none yet): tells the end of a recording
  // from a timeout. Dropped, stale and frozen frames are MonitoredDepthCamera's to judge.
  std::uint64_t last_sequence_ = 0;

  mutable std::mutex health_mutex_;
  CameraHealth health_;
};

}  // namespace

std::unique_ptr<DepthCamera> make_openni2_camera() { return std::make_unique<OpenNI2Camera>(); }

}  // namespace drivers
