#include "drivers/camera_registry.h"

namespace drivers {

// Filled as the back-ends land (V4L2, OpenNI2, replay).
void register_real_depth_cameras() {}

}  // namespace drivers
