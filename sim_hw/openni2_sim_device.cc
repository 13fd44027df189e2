#include "sim_hw/openni2_sim_device.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "sim_hw/d415_model.h"
#include "sim_hw/openni2_sim_property.h"

namespace sim_hw {
namespace {

OniVideoMode oni_mode(const drivers::StreamMode& m, OniPixelFormat format) {
  OniVideoMode mode{};
  mode.pixelFormat = format;
  mode.resolutionX = m.width;
  mode.resolutionY = m.height;
  mode.fps = m.fps;
  return mode;
}

// The simulated D415's modes (d415_model.h) plus the configured one (a source may run at another
// mode in tests).
std::vector<OniVideoMode> advertised(const std::vector<drivers::StreamMode>& d415_modes,
                                     const drivers::StreamMode& configured, OniPixelFormat format) {
  std::vector<OniVideoMode> modes{oni_mode(configured, format)};
  for (const drivers::StreamMode& m : d415_modes) {
    if (m.width == configured.width && m.height == configured.height && m.fps == configured.fps) continue;
    modes.push_back(oni_mode(m, format));
  }
  return modes;
}

// Calibrated intrinsics scaled to a new resolution; none (width 0) stay none, so the source
// camera keeps using its own model.
drivers::Intrinsics scaled(const drivers::Intrinsics& k, int width, int height) {
  if (k.width <= 0 || k.height <= 0 || (k.width == width && k.height == height)) return k;
  drivers::Intrinsics out = k;
  const double sx = double(width) / k.width, sy = double(height) / k.height;
  out.width = width;
  out.height = height;
  out.fx = k.fx * sx;
  out.fy = k.fy * sy;
  out.cx = (k.cx + 0.5) * sx - 0.5;
  out.cy = (k.cy + 0.5) * sy - 0.5;
  return out;
}

// What a stream reports before its first frame brings the source's own intrinsics.
drivers::Intrinsics stream_guess(const drivers::Intrinsics& k, const drivers::StreamMode& m, bool depth) {
  if (k.width == m.width && k.height == m.height) return k;
  return pinhole_from_hfov(m.width, m.height, depth ? kD415DepthHfovDeg : kD415ColorHfovDeg);
}

OniStatus put_string(void* data, int* size, const std::string& text) {
  if (*size < static_cast<int>(text.size()) + 1) return ONI_STATUS_BAD_PARAMETER;
  std::memcpy(data, text.c_str(), text.size() + 1);
  *size = static_cast<int>(text.size()) + 1;
  return ONI_STATUS_OK;
}

}  // namespace

OpenNI2SimDevice::OpenNI2SimDevice(const OpenNI2SimDeviceConfig& config,
                                   std::unique_ptr<drivers::DepthCamera> source,
                                   oni::driver::DriverServices& services, std::function<void()> on_lost)
    : config_(config), source_(std::move(source)), services_(services), on_lost_(std::move(on_lost)) {
  depth_modes_ = advertised(d415_depth_modes(), config_.source.depth_mode, ONI_PIXEL_FORMAT_DEPTH_1_MM);
  sensors_.push_back({ONI_SENSOR_DEPTH, static_cast<int>(depth_modes_.size()), depth_modes_.data()});
  if (config_.has_color) {
    color_modes_ = advertised(d415_color_modes(), config_.source.color_mode, ONI_PIXEL_FORMAT_RGB888);
    sensors_.push_back({ONI_SENSOR_COLOR, static_cast<int>(color_modes_.size()), color_modes_.data()});
  }
}

OpenNI2SimDevice::~OpenNI2SimDevice() {
  stop_ = true;
  if (pump_.joinable()) pump_.join();
  std::lock_guard lock(source_mutex_);
  source_->deactivate();
}

bool OpenNI2SimDevice::start_source() {
  std::lock_guard lock(source_mutex_);
  drivers::DriverResult r = source_->configure(config_.source);
  if (r.ok) r = source_->activate();
  if (!r.ok) {
    services_.errorLoggerAppend("prepreg-sim: source camera of \"%s\" failed: %s",
                                config_.source.name.c_str(), r.message.c_str());
    return false;
  }
  if (!config_.on_demand && !pump_.joinable()) pump_ = std::thread([this] { pump_loop(); });
  return true;
}

OniStatus OpenNI2SimDevice::getSensorInfoList(OniSensorInfo** sensors, int* count) {
  *sensors = sensors_.data();
  *count = static_cast<int>(sensors_.size());
  return ONI_STATUS_OK;
}

oni::driver::StreamBase* OpenNI2SimDevice::createStream(OniSensorType sensor) {
  if (sensor != ONI_SENSOR_DEPTH && !(sensor == ONI_SENSOR_COLOR && config_.has_color)) {
    services_.errorLoggerAppend("prepreg-sim: device \"%s\" has no sensor of type %d",
                                config_.source.name.c_str(), static_cast<int>(sensor));
    return nullptr;
  }
  std::lock_guard source_lock(source_mutex_);
  const bool depth = sensor == ONI_SENSOR_DEPTH;
  const drivers::StreamMode& m = depth ? config_.source.depth_mode : config_.source.color_mode;
  const drivers::Intrinsics& k = depth ? config_.source.depth_intrinsics : config_.source.color_intrinsics;
  auto* stream = new OpenNI2SimStream(
      sensor, depth ? depth_modes_ : color_modes_,
      oni_mode(m, depth ? ONI_PIXEL_FORMAT_DEPTH_1_MM : ONI_PIXEL_FORMAT_RGB888), stream_guess(k, m, depth),
      [this, sensor](const OniVideoMode& mode) { return set_mode(sensor, mode); });
  std::lock_guard lock(streams_mutex_);
  streams_.push_back(stream);
  return stream;
}

void OpenNI2SimDevice::destroyStream(oni::driver::StreamBase* stream) {
  {
    std::lock_guard lock(streams_mutex_);
    streams_.erase(std::remove(streams_.begin(), streams_.end(), stream), streams_.end());
  }
  delete stream;
}

bool OpenNI2SimDevice::set_mode(OniSensorType sensor, const OniVideoMode& mode) {
  std::lock_guard lock(source_mutex_);
  drivers::CameraConfig changed = config_.source;
  drivers::StreamMode& m = sensor == ONI_SENSOR_DEPTH ? changed.depth_mode : changed.color_mode;
  drivers::Intrinsics& k = sensor == ONI_SENSOR_DEPTH ? changed.depth_intrinsics : changed.color_intrinsics;
  m = {mode.resolutionX, mode.resolutionY, mode.fps};
  k = scaled(k, m.width, m.height);
  source_->deactivate();
  drivers::DriverResult r = source_->configure(changed);
  if (r.ok) r = source_->activate();
  if (!r.ok) {
    services_.errorLoggerAppend("prepreg-sim: source camera of \"%s\" refused %dx%d@%d: %s",
                                config_.source.name.c_str(), m.width, m.height, m.fps, r.message.c_str());
    // Put the source back in its previous mode so the device stays usable.
    if (source_->configure(config_.source).ok) source_->activate();
    return false;
  }
  config_.source = changed;
  std::lock_guard streams_lock(streams_mutex_);
  for (OpenNI2SimStream* s : streams_) {
    if (s->sensor() == sensor) s->set_current(mode, stream_guess(k, m, sensor == ONI_SENSOR_DEPTH));
  }
  return true;
}

OniBool OpenNI2SimDevice::isPropertySupported(int property) {
  switch (property) {
    case ONI_DEVICE_PROPERTY_SERIAL_NUMBER:
      return !config_.source.serial.empty();
    case ONI_DEVICE_PROPERTY_FIRMWARE_VERSION:
    case ONI_DEVICE_PROPERTY_DRIVER_VERSION:
    case ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION:
      return TRUE;
    default:
      return FALSE;
  }
}

OniStatus OpenNI2SimDevice::getProperty(int property, void* data, int* size) {
  switch (property) {
    case ONI_DEVICE_PROPERTY_SERIAL_NUMBER:
      if (config_.source.serial.empty()) return ONI_STATUS_NOT_SUPPORTED;
      return put_string(data, size, config_.source.serial);
    case ONI_DEVICE_PROPERTY_FIRMWARE_VERSION:
      return put_string(data, size, "prepreg-sim");
    case ONI_DEVICE_PROPERTY_DRIVER_VERSION:
      return put_property(data, size, OniVersion{1, 0, 0, 0});
    // Registration is done by the reader through depth_to_color, never in the device.
    case ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION:
      return put_property(data, size, static_cast<int>(ONI_IMAGE_REGISTRATION_OFF));
    default:
      return ONI_STATUS_NOT_SUPPORTED;
  }
}

OniStatus OpenNI2SimDevice::setProperty(int property, const void* data, int size) {
  if (property == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION && size == static_cast<int>(sizeof(int))) {
    return *static_cast<const int*>(data) == ONI_IMAGE_REGISTRATION_OFF ? ONI_STATUS_OK
                                                                        : ONI_STATUS_NOT_SUPPORTED;
  }
  return ONI_STATUS_NOT_SUPPORTED;
}

OniStatus OpenNI2SimDevice::tryManualTrigger() {
  if (config_.on_demand) pump_once();
  return ONI_STATUS_OK;
}

void OpenNI2SimDevice::pump_loop() {
  using Clock = std::chrono::steady_clock;
  auto next = Clock::now();
  while (!stop_ && !lost_) {
    bool any_running = false;
    {
      std::lock_guard lock(streams_mutex_);
      for (OpenNI2SimStream* s : streams_) any_running = any_running || s->running();
    }
    if (!any_running) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      next = Clock::now();
      continue;
    }
    pump_once();
    int fps = 30;
    {
      std::lock_guard lock(source_mutex_);
      fps = std::max(1, config_.source.depth_mode.fps);
    }
    next += std::chrono::microseconds(1000000 / fps);
    std::this_thread::sleep_until(next);
  }
}

void OpenNI2SimDevice::pump_once() {
  if (lost_) return;
  {
    std::lock_guard lock(source_mutex_);
    const drivers::ReadStatus status = source_->read(frame_);
    if (status == drivers::ReadStatus::kFrame || status == drivers::ReadStatus::kStale ||
        status == drivers::ReadStatus::kFrozen) {
      // Stale and frozen frames too: a real device delivers them just the same.
      std::lock_guard streams_lock(streams_mutex_);
      for (OpenNI2SimStream* s : streams_) s->push(frame_);
      return;
    }
    if (status != drivers::ReadStatus::kLost) return;  // timeout: nothing this time
  }
  // Outside the lock: OpenNI2 runs its disconnect listeners inside this call.
  if (!lost_.exchange(true)) on_lost_();
}

}  // namespace sim_hw
