#include "drivers/openni2_recorder.h"

#include <OpenNI.h>

#include <chrono>
#include <cstring>
#include <thread>

#include <fmt/format.h>

#include "drivers/openni2_modes.h"
#include "drivers/openni2_runtime.h"

namespace drivers {
namespace {

constexpr std::chrono::milliseconds kRecorderStartDelay{100};

// Owns the OpenNI2 objects of one recording so every exit path releases them in order.
struct RecordingSession {
  openni::Device device;
  openni::VideoStream depth, color;
  openni::Recorder recorder;
  ~RecordingSession() {
    if (recorder.isValid()) {
      recorder.stop();
      recorder.destroy();  // writes the seek tables and closes the file
    }
    for (openni::VideoStream* s : {&depth, &color}) {
      if (s->isValid()) {
        s->stop();
        s->destroy();
      }
    }
    if (device.isValid()) device.close();
  }
};

DriverResult open_streams(const CameraConfig& config, RecordingSession& session) {
  const bool any = config.uri == "any";
  if (session.device.open(any ? openni::ANY_DEVICE : config.uri.c_str()) != openni::STATUS_OK) {
    return DriverResult::failure(
        fmt::format("cannot open OpenNI2 device \"{}\": {}", config.uri, openni2_error_text()));
  }
  if (!config.serial.empty()) {
    char serial[ONI_MAX_STR] = {};
    int size = sizeof(serial);
    if (session.device.getProperty(ONI_DEVICE_PROPERTY_SERIAL_NUMBER, serial, &size) != openni::STATUS_OK ||
        config.serial != std::string(serial, strnlen(serial, sizeof(serial)))) {
      return DriverResult::failure(fmt::format("device \"{}\" is not serial \"{}\" (it reports \"{}\")",
                                               config.uri, config.serial, serial));
    }
  }
  if (session.depth.create(session.device, openni::SENSOR_DEPTH) != openni::STATUS_OK) {
    return DriverResult::failure("cannot create the depth stream: " + openni2_error_text());
  }
  DriverResult mode =
      select_openni2_mode(session.depth, config.depth_mode, openni::PIXEL_FORMAT_DEPTH_1_MM, "depth");
  if (!mode.ok || !session.device.hasSensor(openni::SENSOR_COLOR)) return mode;
  if (session.color.create(session.device, openni::SENSOR_COLOR) != openni::STATUS_OK) {
    return DriverResult::failure("cannot create the colour stream: " + openni2_error_text());
  }
  return select_openni2_mode(session.color, config.color_mode, openni::PIXEL_FORMAT_RGB888, "colour");
}

}  // namespace

DriverResult record_openni2_session(const CameraConfig& config, const std::string& oni_path, int depth_frames,
                                    OpenNI2RecordingStats* stats) {
  OpenNI2Runtime runtime;
  if (!runtime.ok()) return DriverResult::failure(runtime.message());
  OpenNI2RecordingStats counts;
  RecordingSession session;
  DriverResult opened = open_streams(config, session);
  if (!opened.ok) return DriverResult::failure(config.name + ": " + opened.message);
  if (session.recorder.create(oni_path.c_str()) != openni::STATUS_OK) {
    return DriverResult::failure(
        fmt::format("cannot create recording \"{}\": {}", oni_path, openni2_error_text()));
  }
  const bool has_color = session.color.isValid();
  // Lossy (JPEG) compression off: a replay must give back exactly what the camera saw.
  if (session.recorder.attach(session.depth, false) != openni::STATUS_OK ||
      (has_color && session.recorder.attach(session.color, false) != openni::STATUS_OK)) {
    return DriverResult::failure("cannot attach the streams to the recorder: " + openni2_error_text());
  }
  if (session.depth.start() != openni::STATUS_OK ||
      (has_color && session.color.start() != openni::STATUS_OK) ||
      session.recorder.start() != openni::STATUS_OK) {
    return DriverResult::failure("cannot start recording: " + openni2_error_text());
  }
  // openni::Recorder::start() only queues a message to the recorder's own thread, and frames that
  // arrive before that thread has processed it are silently not recorded. Give it time to start
  // before asking the device for frames (an on-demand device makes none meanwhile).
  std::this_thread::sleep_for(kRecorderStartDelay);
  openni::VideoStream* streams[2] = {&session.depth, &session.color};
  openni::VideoFrameRef frame;
  // Until the depth frames are in, and the colour taken with the last of them (a replay pairs
  // each depth frame with its colour).
  while (counts.depth_frames < depth_frames || (has_color && counts.color_frames < depth_frames)) {
    int ready = -1;
    const openni::Status rc = openni::OpenNI::waitForAnyStream(streams, has_color ? 2 : 1, &ready,
                                                               static_cast<int>(config.read_timeout.count()));
    if (rc != openni::STATUS_OK) {
      return DriverResult::failure(fmt::format("recording {} stopped after {} depth frames: {}", oni_path,
                                               counts.depth_frames, openni2_error_text()));
    }
    if (streams[ready]->readFrame(&frame) != openni::STATUS_OK) {
      return DriverResult::failure("reading a frame failed: " + openni2_error_text());
    }
    ++(ready == 0 ? counts.depth_frames : counts.color_frames);
  }
  if (stats != nullptr) *stats = counts;
  return DriverResult::success();
}

}  // namespace drivers
