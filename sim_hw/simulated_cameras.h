#pragma once
// Registers sim_hw's depth-camera stand-ins with the drivers/ registry (see
// drivers/camera_registry.h), so a cell config can name them like any real back-end.

namespace sim_hw {

// Registers back-end "simulated" (a ray-cast D415 looking at a scene; see simulated_d415.h).
void register_simulated_depth_cameras();

}  // namespace sim_hw
