#include "sim_hw/simulated_cameras.h"

#include "drivers/camera_registry.h"
#include "sim_hw/simulated_d415.h"

namespace sim_hw {

void register_simulated_depth_cameras() {
  // The registered camera reads its scene from CameraConfig::uri (a scene JSON file); code that
  // drives a live scene constructs SimulatedD415Camera with a SceneSource instead.
  drivers::register_depth_camera_backend("simulated", [] { return std::make_unique<SimulatedD415Camera>(); });
}

}  // namespace sim_hw
