// The cell controller's handlers: the controller's own (SIM_SHEET_TRUTH, SIM_FAULT with fault
// injection on, cell/cell_controller.h) and the robot link's (IIWA_STATUS_<ARM>,
// GRIPPER_STATUS_<G>, cell/robot_link.h), with the fake cell's config, then what a cycle does with
// them: jaw positions by forward kinematics, staleness, targets advanced and arm commands published.
#include <memory>

#include "cell/cell_config.h"
#include "cell/cell_controller.h"
#include "cell/robot_link.h"
#include "tests/fuzz/lcm_fuzz_support.h"
#include "tests/fuzz/lcm_harness_channels.h"
#include "twin/trials/grasp_plan.h"

namespace {

struct Cell {
  drivers::LcmBus bus{"memq://"};
  cell::CellConfig config = cell::read_cell_config(PREPREG_SOURCE_DIR "/cell/examples/fake_cell.json");
  twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
  std::vector<std::string> channels = fuzz::cell_channels(config.hardware);
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Cell cell;
  cell::CellController controller(cell.config, cell.bus, /*fault_injection=*/true);
  cell::RobotLink robots(cell.bus, cell.config.hardware, cell.plan);
  fuzz::deliver(cell.bus, fuzz::split_messages(data, size, cell.channels));
  // What a cycle does with what arrived.
  for (int g = 0; g < robots.gripper_count(); ++g) (void)robots.jaw_position(g);
  (void)robots.stale_arms(drivers::host_clock_us(), 200.0);
  robots.advance_targets(1.0 / 30, 0.05);
  robots.command_arms(1.0 / 30, 0.5);
  (void)controller.truth();
  (void)controller.dropped_messages();
  // The commands went out on the bus: drain them so the next input starts empty.
  while (cell.bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
  }
  return 0;
}
