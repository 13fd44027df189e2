#pragma once
// One cell under test: files in a temp dir, the memq bus, the simulated cameras, the responder
// and the controller, built in that order and torn down in reverse; plus a listener that counts
// what the cell publishes.
#include <functional>
#include <map>
#include <memory>

#include "cell/cell_controller.h"
#include "drivers/lcm_channels.h"
#include "tests/cell/cell_rig.h"

namespace cell_test {

struct Listener {
  std::map<std::string, int> count;
  prepreg_lcm::cell_state_t last_state{};
  prepreg_lcm::prediction_error_t last_error{};
  prepreg_lcm::sheet_state_t last_observed{}, last_predicted{};
  std::map<std::string, prepreg_lcm::camera_status_t> cameras;

  explicit Listener(drivers::LcmBus& bus) {
    using namespace drivers::channels;
    bus.subscribe<prepreg_lcm::cell_state_t>(std::string(kCellState), [this](const auto& m) {
      ++count["CELL_STATE"];
      last_state = m;
    });
    bus.subscribe<prepreg_lcm::prediction_error_t>(std::string(kPredictionError), [this](const auto& m) {
      ++count["PREDICTION_ERROR"];
      last_error = m;
    });
    bus.subscribe<prepreg_lcm::sheet_state_t>(std::string(kSheetObserved), [this](const auto& m) {
      ++count["SHEET_OBSERVED"];
      last_observed = m;
    });
    bus.subscribe<prepreg_lcm::sheet_state_t>(std::string(kSheetPredicted), [this](const auto& m) {
      ++count["SHEET_PREDICTED"];
      last_predicted = m;
    });
    bus.subscribe_with_channel<prepreg_lcm::camera_status_t>(
        "CAMERA_STATUS_.*", [this](const std::string& channel, const auto& m) {
          ++count[channel];
          cameras[m.name] = m;
        });
    bus.subscribe<prepreg_lcm::grasp_plan_t>(std::string(kGraspPlan), [this](const auto&) { ++count["GRASP_PLAN"]; });
  }
};

struct CellUnderTest {
  testing_support::TempDir dir{"cell_rig"};
  cell::CellConfig config;
  drivers::LcmBus bus{"memq://"};
  Listener listener{bus};
  std::unique_ptr<SimCameras> cameras;
  std::unique_ptr<Responder> responder;
  std::unique_ptr<cell::CellController> controller;

  explicit CellUnderTest(const RigFiles& files, bool fault_injection = false,
                         const std::function<void(CellUnderTest&)>& before_start = {}) {
    config = cell::read_cell_config(write_files(dir, files));
    cameras = std::make_unique<SimCameras>(config);
    responder = std::make_unique<Responder>(bus, config);
    if (before_start) before_start(*this);
    controller = std::make_unique<cell::CellController>(config, bus, fault_injection);
  }
  ~CellUnderTest() {
    controller.reset();
    responder.reset();
  }
  // Cycles until `until` holds for the report (at most max_cycles); the last report.
  cell::CycleReport run(int max_cycles, const std::function<bool(const cell::CycleReport&)>& until = {}) {
    cell::CycleReport r;
    for (int i = 0; i < max_cycles; ++i) {
      const std::int64_t start_us = drivers::host_clock_us();
      r = controller->cycle();
      // To the next cycle's start: on the simulation clock the rig's responder runs the clock
      // there (cell_rig.h); on the wall the cameras' reads pace the cycles.
      if (controller->sim_clock()) controller->wait_until(controller->next_cycle_start_us(start_us, r));
      else controller->handle_bus(0);
      if (until && until(r)) break;
    }
    return r;
  }
};

}  // namespace cell_test
