#pragma once
// Stream-mode negotiation for the OpenNI2 back-end: pick the device's VideoMode that matches the
// configured resolution, rate and pixel format, or explain which modes the device offers.
// Header kept free of OpenNI.h so only the back-end's .cc files see OpenNI2.

#include <string>

#include "drivers/depth_camera.h"

namespace openni {
class VideoStream;
}

namespace drivers {

// Sets `stream` to the mode `wanted` with pixel format `pixel_format` (an openni::PixelFormat
// value). Fails naming the sensor and listing every mode the device offers when none matches.
// A stream already in that mode is left alone (recordings cannot change mode).
DriverResult select_openni2_mode(openni::VideoStream& stream, const StreamMode& wanted, int pixel_format,
                                 const std::string& sensor_name);

// The modes the stream's sensor offers, e.g. "848x480@30fps depth 1 mm, 1280x720@30fps ...".
std::string describe_openni2_modes(const openni::VideoStream& stream);

// Pinhole intrinsics of a width x height image from OpenNI2's field of view (radians), principal
// point at the image centre: what a device without calibration data tells us.
Intrinsics intrinsics_from_fov(int width, int height, double horizontal_fov_rad, double vertical_fov_rad);

}  // namespace drivers
