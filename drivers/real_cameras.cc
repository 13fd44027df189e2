#include "drivers/camera_registry.h"
#include "drivers/openni2_camera.h"
#include "drivers/replay_camera.h"

namespace drivers {

// Filled as the back-ends land (V4L2, OpenNI2, replay).
void register_real_depth_cameras() {
  register_depth_camera_backend("replay", [] { return std::make_unique<ReplayDepthCamera>(); });
  register_depth_camera_backend("openni2", make_openni2_camera);
}

}  // namespace drivers
