#include "drivers/camera_registry.h"
#include "drivers/openni2_camera.h"
#include "drivers/v4l2_d415_camera.h"
#include "drivers/replay_camera.h"

namespace drivers {

void register_real_depth_cameras() {
  register_depth_camera_backend("v4l2", [] { return std::make_unique<V4l2D415Camera>(); });
  register_depth_camera_backend("replay", [] { return std::make_unique<ReplayDepthCamera>(); });
  register_depth_camera_backend("openni2", make_openni2_camera);
}

}  // namespace drivers
