#pragma once
// Depth camera back-end "openni2": a device or an .oni recording read through OpenNI2's own C++
// API (libOpenNI2 and whatever drivers its repository holds).
//
// CameraConfig::uri is an OpenNI2 device URI, "any" for the first device OpenNI2 lists, or the
// path of an .oni recording (played by OpenNI2's OniFile driver). A recording may carry a
// playback speed: "session.oni?speed=1" plays in real time; the default, -1, is OpenNI2's
// "manual" speed: each read gets the next frame as fast as the reader asks (CI, benchmarks).
//
// Depth is read as PIXEL_FORMAT_DEPTH_1_MM at config.depth_mode, colour as RGB888 at
// config.color_mode when the device has a colour sensor; OpenNI2's image registration stays off
// because the tracker maps colour through depth_to_color itself. A disconnected device makes
// read() return kLost and later reads try to reopen it (at most once per read_timeout; OpenNI2
// only reopens a URI its driver has announced again, as after a USB replug); the end of a
// recording makes read() return kTimeout with health().message starting "end of recording".
//
// Intrinsics: config.depth_intrinsics / color_intrinsics (the unit's calibration) when their size
// matches the frame; otherwise pinhole intrinsics from the field of view OpenNI2 reports, with
// the principal point at the image centre (OpenNI2 carries no more than the FOV).
// sequence = OpenNI2's frame index, device_time_us = its timestamp (us). read() reports only what
// the driver knows (kFrame, kTimeout, kLost, kNotActive) and counts frames in health(); dropped,
// stale and frozen frames are judged by MonitoredDepthCamera (make_monitored_depth_camera).

#include <memory>

#include "drivers/depth_camera.h"

namespace drivers {

std::unique_ptr<DepthCamera> make_openni2_camera();

}  // namespace drivers
