// The experiment runner on the in-process cell: states with a move and a release, the table's
// columns filled from the cycles, the truth columns from SIM_SHEET_TRUTH.
#include <catch2/catch.hpp>

#include "cell/experiment_runner.h"
#include "tests/cell/cell_fixture.h"

using cell::CellState;

TEST_CASE("experiment: move and release states are applied, settled and measured", "[cell]") {
  cell_test::RigFiles f = cell_test::default_files();
  f.config["tracker"]["fusion"] = {{"pixel_stride", 4}};
  cell_test::CellUnderTest t(f);
  REQUIRE(t.controller->startup() == CellState::kReady);

  cell::Experiment e;
  e.window_s = 0.5;
  e.states.push_back({"four grasps", {}, 0.4});
  cell::ExperimentAction raise{cell::ExperimentAction::Kind::kMove, "CENTER", twin::Vec3::Zero()};
  const twin::GraspPlan& plan = t.controller->plan();
  raise.to_m = plan.grasps[plan.index_of("CENTER")].hold_position_m + twin::Vec3(0, 0, 0.01);
  e.states.push_back({"CENTER raised 1 cm", {raise}, 0.4});
  e.states.push_back({"MANUAL released", {{cell::ExperimentAction::Kind::kRelease, "MANUAL", {}}}, 0.4});
  cell::ExperimentRunner runner(e);

  // The fake world's truth: the sheet as rendered (it does not follow the cell's actions here,
  // so twin and truth part after the release).
  prepreg_lcm::sheet_state_t truth{};
  truth.source = prepreg_lcm::sheet_state_t::SOURCE_OBSERVED;
  for (const auto& p : t.cameras->truth()) {
    truth.x_m.push_back(static_cast<float>(p.x()));
    truth.y_m.push_back(static_cast<float>(p.y()));
    truth.z_m.push_back(static_cast<float>(p.z()));
  }
  truth.num_vertices = static_cast<int>(truth.x_m.size());
  truth.coverage = 1.0f;

  const auto gripper_commands = t.responder->gripper_commands();
  for (int i = 0; i < 200 && !runner.done(); ++i) {
    truth.utime = drivers::utime_now();
    REQUIRE(t.bus.publish(std::string(drivers::channels::kSimTruth), truth));
    t.controller->handle_bus(0);
    const cell::CycleReport r = t.controller->cycle();
    runner.on_cycle(*t.controller, r);
  }
  INFO(runner.current() << "\n" << cell::format_results(runner.results()));
  REQUIRE(runner.done());
  const auto& res = runner.results();
  REQUIRE(res.size() == 3);
  for (const auto& s : res) {
    CHECK(s.cycles >= 1);
    CHECK(s.prediction.samples >= 1);
    CHECK(s.twin_vs_truth.samples >= 1);
  }
  // Before anything moved, the twin is the truth's own equilibrium: millimetres apart.
  CHECK(res[0].twin_vs_truth.mean_m < 0.003);
  CHECK(res[0].tracked_vs_truth.mean_m < 0.01);
  // MANUAL let go in the twin (the gripper reported open) but not in the rendered truth.
  CHECK(t.responder->gripper_commands() > gripper_commands);
  CHECK_FALSE(t.responder->holding("MANUAL"));
  CHECK(t.controller->released("MANUAL"));
  CHECK(res[2].twin_vs_truth.mean_m > 0.01);
  CHECK(res[2].twin_vs_truth.mean_m > 10 * res[0].twin_vs_truth.mean_m);
  CHECK(cell::results_json(res)["states"].size() == 3);
  WARN(cell::format_results(res));
}
