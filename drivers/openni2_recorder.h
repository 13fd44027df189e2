#pragma once
// Records a live OpenNI2 session into an .oni file with OpenNI2's own openni::Recorder, so a run
// on a real cell can be kept in OpenNI2's format and replayed later through the "openni2" back-end
// (CameraConfig::uri = the .oni path). Depth is stored losslessly (OpenNI2's 16z codec), colour
// uncompressed.

#include <string>

#include "drivers/depth_camera.h"

namespace drivers {

struct OpenNI2RecordingStats {
  int depth_frames = 0;  // depth frames read while recording (OpenNI2 records every frame the
                         // driver delivers, which for a free-running device can be more)
  int color_frames = 0;
};

// Opens config.uri as the "openni2" back-end would (depth_mode, color_mode, serial check), records
// until `depth_frames` depth frames were read, then closes the file. Fails when the device cannot
// be opened, a mode is missing, the file cannot be written, or config.read_timeout passes without a
// frame (the message says how many frames were recorded).
DriverResult record_openni2_session(const CameraConfig& config, const std::string& oni_path, int depth_frames,
                                    OpenNI2RecordingStats* stats = nullptr);

}  // namespace drivers
