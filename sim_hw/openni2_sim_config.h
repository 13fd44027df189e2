#pragma once
// The device list of the OpenNI2 simulation plug-in (libprepreg_openni2_sim): a JSON file named
// by the environment variable PREPREG_OPENNI2_SIM_CONFIG, one entry per simulated D415. Each
// entry is the CameraConfig of the SOURCE camera the plug-in reads frames from (any registered
// back-end, normally "simulated"), plus how the plug-in presents it:
//
//   [ { "name": "cam_left",                       OpenNI2 URI "prepreg-sim://cam_left"
//       "backend": "simulated", "uri": "...",      source camera (back-end's own uri)
//       "serial": "821312060001",                  reported as ONI_DEVICE_PROPERTY_SERIAL_NUMBER
//       "depth_mode": {"width": 848, "height": 480, "fps": 30},
//       "color_mode": {"width": 848, "height": 480, "fps": 30},   optional; absent = no colour
//       "depth_intrinsics": {"width":848,"height":480,"fx":..,"fy":..,"cx":..,"cy":..}, optional
//       "color_intrinsics": {...},                 optional
//       "depth_to_color": [16 numbers, row-major 4x4, m], "camera_to_cell": [...],  optional
//       "read_timeout_ms": 200,                    optional
//       "on_demand": false,     true: a frame only when OpenNI2 waits for one (CI determinism)
//       "replug_after_ms": 500  after the source dies the device re-appears; -1 = never
//   } ]

#include <string>
#include <vector>

#include "drivers/depth_camera.h"

namespace sim_hw {

inline constexpr const char* kOpenNI2SimConfigVariable = "PREPREG_OPENNI2_SIM_CONFIG";
inline constexpr const char* kOpenNI2SimUriPrefix = "prepreg-sim://";

struct OpenNI2SimDeviceConfig {
  drivers::CameraConfig source;  // source.serial is what the device reports
  bool has_color = false;
  bool on_demand = false;
  int replug_after_ms = -1;
};

// Throws std::runtime_error naming the file and field when the file is unreadable or wrong.
std::vector<OpenNI2SimDeviceConfig> read_openni2_sim_config(const std::string& path);

}  // namespace sim_hw
