#include "sim_hw/simulated_cameras.h"

#include "drivers/camera_registry.h"

namespace sim_hw {

// Filled as the simulated D415 lands.
void register_simulated_depth_cameras() {}

}  // namespace sim_hw
