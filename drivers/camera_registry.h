#pragma once
// Depth-camera back-ends by name, so the cell opens whatever its config asks for ("v4l2",
// "openni2", "replay", "simulated") without knowing which library provides it. Registration is
// explicit (a static library's self-registering globals can be dropped by the linker): drivers/
// registers its real back-ends in register_real_depth_cameras(); sim_hw/ registers its
// stand-ins in its own function; the cell calls both at start-up.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"

namespace drivers {

using DepthCameraFactory = std::function<std::unique_ptr<DepthCamera>()>;

// Adds or replaces a back-end.
void register_depth_camera_backend(const std::string& backend, DepthCameraFactory factory);

// A new, unconfigured camera of that back-end. Throws std::invalid_argument naming the unknown
// back-end and the registered ones.
std::unique_ptr<DepthCamera> make_depth_camera(const std::string& backend);

std::vector<std::string> depth_camera_backends();

// Registers the back-ends that drivers/ implements (V4L2, OpenNI2, replay of recordings).
void register_real_depth_cameras();

}  // namespace drivers
