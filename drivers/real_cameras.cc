#include "drivers/camera_registry.h"
#include "drivers/v4l2_d415_camera.h"
#include "drivers/replay_camera.h"

namespace drivers {

// Filled as the back-ends land (V4L2, OpenNI2, replay).
void register_real_depth_cameras() {
  register_depth_camera_backend("v4l2", [] { return std::make_unique<V4l2D415Camera>(); });
  register_depth_camera_backend("replay", [] { return std::make_unique<ReplayDepthCamera>(); });
}

}  // namespace drivers
