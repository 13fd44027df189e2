// The fake world's handlers (sim_hw/cell_world.h): IIWA_COMMAND_<ARM>, GRIPPER_COMMAND_<G>,
// SIM_FAULT and its lockstep client's SIM_CLOCK_HOLD, as cell_world receives them from the cell
// (or anyone on the bus), then a few milliseconds of the world's loop that follow the commands
// and publish statuses. The world is built once (its
// sheet's first load takes seconds), so its state carries over from input to input, as a running
// world's does.
#include <chrono>
#include <memory>

#include "sim_hw/cell_world.h"
#include "sim_hw/world_config.h"
#include "tests/fuzz/lcm_fuzz_support.h"
#include "tests/fuzz/lcm_harness_channels.h"

namespace {

struct World {
  drivers::LcmBus bus{"memq://"};
  sim_hw::WorldConfig config = sim_hw::read_world_config(PREPREG_SOURCE_DIR "/cell/examples/fake_cell.json",
                                                         PREPREG_SOURCE_DIR "/sim_hw/examples/fake_world.json");
  std::vector<std::string> channels = fuzz::world_channels(config.hardware);
  // As fast as it goes (no real-time wait), held by the cell controller as in the fake cell.
  sim_hw::CellWorld world{config, bus, sim_hw::WorldClockOptions{0.0, {"cell_controller"}, 30.0}};
};

World* world = nullptr;

}  // namespace

// The world is built before fuzzing starts, outside the per-input timeout.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  world = new World;
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  World& w = *world;
  for (const auto& m : fuzz::split_messages(data, size, w.channels)) {
    w.bus.publish_raw(m.channel, m.payload.data(), m.payload.size());
  }
  // The world's LCM thread: handles what arrived, ticks the arms and grippers, publishes statuses.
  w.world.run_for(std::chrono::milliseconds(2));
  return 0;
}
