#include "drivers/openni2_modes.h"

#include <OpenNI.h>

#include <cmath>

#include <fmt/format.h>

#include "drivers/openni2_runtime.h"

namespace drivers {
namespace {

std::string pixel_format_name(openni::PixelFormat format) {
  switch (format) {
    case openni::PIXEL_FORMAT_DEPTH_1_MM:
      return "depth 1 mm";
    case openni::PIXEL_FORMAT_DEPTH_100_UM:
      return "depth 100 um";
    case openni::PIXEL_FORMAT_SHIFT_9_2:
      return "shift 9.2";
    case openni::PIXEL_FORMAT_SHIFT_9_3:
      return "shift 9.3";
    case openni::PIXEL_FORMAT_RGB888:
      return "RGB888";
    case openni::PIXEL_FORMAT_YUV422:
      return "YUV422";
    case openni::PIXEL_FORMAT_GRAY8:
      return "gray 8";
    case openni::PIXEL_FORMAT_GRAY16:
      return "gray 16";
    case openni::PIXEL_FORMAT_JPEG:
      return "JPEG";
    case openni::PIXEL_FORMAT_YUYV:
      return "YUYV";
  }
  return fmt::format("pixel format {}", static_cast<int>(format));
}

std::string describe(const openni::VideoMode& mode) {
  return fmt::format("{}x{}@{}fps {}", mode.getResolutionX(), mode.getResolutionY(), mode.getFps(),
                     pixel_format_name(mode.getPixelFormat()));
}

bool matches(const openni::VideoMode& mode, const StreamMode& wanted, int pixel_format) {
  return mode.getResolutionX() == wanted.width && mode.getResolutionY() == wanted.height &&
         mode.getFps() == wanted.fps && static_cast<int>(mode.getPixelFormat()) == pixel_format;
}

}  // namespace

std::string describe_openni2_modes(const openni::VideoStream& stream) {
  const openni::Array<openni::VideoMode>& modes = stream.getSensorInfo().getSupportedVideoModes();
  std::string text;
  for (int i = 0; i < modes.getSize(); ++i) text += (i > 0 ? ", " : "") + describe(modes[i]);
  return text.empty() ? "none" : text;
}

DriverResult select_openni2_mode(openni::VideoStream& stream, const StreamMode& wanted, int pixel_format,
                                 const std::string& sensor_name) {
  if (matches(stream.getVideoMode(), wanted, pixel_format)) return DriverResult::success();
  const openni::Array<openni::VideoMode>& modes = stream.getSensorInfo().getSupportedVideoModes();
  const std::string wanted_text =
      fmt::format("{}x{}@{}fps {}", wanted.width, wanted.height, wanted.fps,
                  pixel_format_name(static_cast<openni::PixelFormat>(pixel_format)));
  for (int i = 0; i < modes.getSize(); ++i) {
    if (!matches(modes[i], wanted, pixel_format)) continue;
    if (stream.setVideoMode(modes[i]) != openni::STATUS_OK) {
      return DriverResult::failure(
          fmt::format("{} stream refused mode {}: {}", sensor_name, wanted_text, openni2_error_text()));
    }
    return DriverResult::success();
  }
  return DriverResult::failure(fmt::format("{} stream has no mode {}; the device offers: {}", sensor_name,
                                           wanted_text, describe_openni2_modes(stream)));
}

Intrinsics intrinsics_from_fov(int width, int height, double horizontal_fov_rad, double vertical_fov_rad) {
  Intrinsics k;
  k.width = width;
  k.height = height;
  k.fx = 0.5 * width / std::tan(0.5 * horizontal_fov_rad);
  k.fy = 0.5 * height / std::tan(0.5 * vertical_fov_rad);
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

}  // namespace drivers
