#include "sim_hw/openni2_sim_stream.h"

#include <cmath>
#include <cstring>

#include "sim_hw/openni2_sim_property.h"

namespace sim_hw {
namespace {

constexpr int kMaxDepthMm = 65535;  // Z16: the whole uint16 range is a valid distance

int bytes_per_pixel(OniSensorType sensor) { return sensor == ONI_SENSOR_DEPTH ? 2 : 3; }

}  // namespace

OpenNI2SimStream::OpenNI2SimStream(OniSensorType sensor, const std::vector<OniVideoMode>& modes,
                                   OniVideoMode current, drivers::Intrinsics intrinsics,
                                   std::function<bool(const OniVideoMode&)> set_mode)
    : sensor_(sensor),
      modes_(modes),
      current_(current),
      intrinsics_(intrinsics),
      set_mode_(std::move(set_mode)) {}

OniStatus OpenNI2SimStream::start() {
  running_ = true;
  return ONI_STATUS_OK;
}

void OpenNI2SimStream::stop() { running_ = false; }

void OpenNI2SimStream::set_current(const OniVideoMode& mode, const drivers::Intrinsics& intrinsics) {
  current_ = mode;
  std::lock_guard lock(intrinsics_mutex_);
  intrinsics_ = intrinsics;
}

OniBool OpenNI2SimStream::isPropertySupported(int property) {
  switch (property) {
    case ONI_STREAM_PROPERTY_VIDEO_MODE:
    case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
    case ONI_STREAM_PROPERTY_VERTICAL_FOV:
    case ONI_STREAM_PROPERTY_MIRRORING:
    case ONI_STREAM_PROPERTY_CROPPING:
    case ONI_STREAM_PROPERTY_STRIDE:
      return TRUE;
    case ONI_STREAM_PROPERTY_MAX_VALUE:
    case ONI_STREAM_PROPERTY_MIN_VALUE:
      return sensor_ == ONI_SENSOR_DEPTH;
    default:
      return FALSE;
  }
}

OniStatus OpenNI2SimStream::getProperty(int property, void* data, int* size) {
  switch (property) {
    case ONI_STREAM_PROPERTY_VIDEO_MODE:
      return put_property(data, size, current_);
    // Field of view from the pinhole intrinsics (rad), as a D415 reports it.
    case ONI_STREAM_PROPERTY_HORIZONTAL_FOV: {
      std::lock_guard lock(intrinsics_mutex_);
      return put_property(data, size, static_cast<float>(2.0 * std::atan(0.5 * intrinsics_.width / intrinsics_.fx)));
    }
    case ONI_STREAM_PROPERTY_VERTICAL_FOV: {
      std::lock_guard lock(intrinsics_mutex_);
      return put_property(data, size, static_cast<float>(2.0 * std::atan(0.5 * intrinsics_.height / intrinsics_.fy)));
    }
    case ONI_STREAM_PROPERTY_MIRRORING:
      return put_property<OniBool>(data, size, FALSE);
    case ONI_STREAM_PROPERTY_CROPPING: {
      OniCropping none{};
      none.enabled = FALSE;
      return put_property(data, size, none);
    }
    case ONI_STREAM_PROPERTY_STRIDE:
      return put_property(data, size, current_.resolutionX * bytes_per_pixel(sensor_));
    case ONI_STREAM_PROPERTY_MAX_VALUE:
      return sensor_ == ONI_SENSOR_DEPTH ? put_property(data, size, kMaxDepthMm) : ONI_STATUS_NOT_SUPPORTED;
    case ONI_STREAM_PROPERTY_MIN_VALUE:
      return sensor_ == ONI_SENSOR_DEPTH ? put_property(data, size, 0) : ONI_STATUS_NOT_SUPPORTED;
    default:
      return ONI_STATUS_NOT_SUPPORTED;
  }
}

OniStatus OpenNI2SimStream::setProperty(int property, const void* data, int size) {
  switch (property) {
    case ONI_STREAM_PROPERTY_VIDEO_MODE: {
      if (size != static_cast<int>(sizeof(OniVideoMode))) return ONI_STATUS_BAD_PARAMETER;
      OniVideoMode wanted;
      std::memcpy(&wanted, data, sizeof(wanted));
      for (const OniVideoMode& m : modes_) {
        if (m.pixelFormat == wanted.pixelFormat && m.resolutionX == wanted.resolutionX &&
            m.resolutionY == wanted.resolutionY && m.fps == wanted.fps) {
          return set_mode_(wanted) ? ONI_STATUS_OK : ONI_STATUS_ERROR;
        }
      }
      return ONI_STATUS_NOT_SUPPORTED;
    }
    // A D415 has no mirroring or cropping; turning them off is the only valid request.
    case ONI_STREAM_PROPERTY_MIRRORING: {
      if (size != static_cast<int>(sizeof(OniBool))) return ONI_STATUS_BAD_PARAMETER;
      return *static_cast<const OniBool*>(data) == FALSE ? ONI_STATUS_OK : ONI_STATUS_NOT_SUPPORTED;
    }
    case ONI_STREAM_PROPERTY_CROPPING: {
      if (size != static_cast<int>(sizeof(OniCropping))) return ONI_STATUS_BAD_PARAMETER;
      return static_cast<const OniCropping*>(data)->enabled == FALSE ? ONI_STATUS_OK
                                                                     : ONI_STATUS_NOT_SUPPORTED;
    }
    default:
      return ONI_STATUS_NOT_SUPPORTED;
  }
}

bool OpenNI2SimStream::push(const drivers::DepthFrame& frame) {
  const int width = current_.resolutionX, height = current_.resolutionY;
  const std::size_t bytes = static_cast<std::size_t>(width) * height * bytes_per_pixel(sensor_);
  const bool depth = sensor_ == ONI_SENSOR_DEPTH;
  const void* source = depth ? static_cast<const void*>(frame.depth_mm.data()) : frame.rgb.data();
  const std::size_t source_bytes = depth ? frame.depth_mm.size() * 2 : frame.rgb.size();
  if (!running_ || source_bytes != bytes) return false;
  {
    std::lock_guard lock(intrinsics_mutex_);
    intrinsics_ = depth ? frame.depth_intrinsics : frame.color_intrinsics;
  }
  OniFrame* out = getServices().acquireFrame();
  if (out == nullptr) return false;
  if (static_cast<std::size_t>(out->dataSize) < bytes) {
    getServices().releaseFrame(out);
    return false;
  }
  std::memcpy(out->data, source, bytes);
  out->frameIndex = static_cast<int>(frame.sequence);
  out->timestamp = static_cast<uint64_t>(frame.device_time_us);
  out->videoMode = current_;
  out->width = width;
  out->height = height;
  out->cropOriginX = out->cropOriginY = 0;
  out->croppingEnabled = FALSE;
  out->sensorType = sensor_;
  out->stride = width * bytes_per_pixel(sensor_);
  raiseNewFrame(out);
  getServices().releaseFrame(out);
  return true;
}

}  // namespace sim_hw
