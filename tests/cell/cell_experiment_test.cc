// The experiment runner on the in-process cell: states with a move and a release, the table's
// columns filled from the cycles, the truth columns from SIM_SHEET_TRUTH.
#include <catch2/catch.hpp>

#include <fstream>

#include "cell/experiment_comparison.h"
#include "cell/experiment_runner.h"
#include "tests/cell/cell_fixture.h"
#include "tests/support/temp_dir.h"

using Catch::Matchers::Contains;

using cell::CellState;

TEST_CASE("experiment: move and release states are applied, settled and measured", "[cell][real_time]") {
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
    const cell::CycleReport r = t.run(1);
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

namespace {
cell::StateResult state(const std::string& name, double prediction_mean_m, double truth_mean_m) {
  cell::StateResult r;
  r.name = name;
  r.prediction.add(prediction_mean_m, 4 * prediction_mean_m);
  r.alg1.add(prediction_mean_m, 4 * prediction_mean_m);
  if (truth_mean_m > 0) {
    r.twin_vs_truth.add(truth_mean_m, 5 * truth_mean_m);
    r.tracked_vs_truth.add(0.004, 0.02);
  }
  r.cycles = 1;
  return r;
}
}  // namespace

TEST_CASE("two runs' experiment files read back and compare state by state", "[cell]") {
  testing_support::TempDir dir("experiment_comparison");
  const std::vector<cell::StateResult> before = {state("four grasps", 0.010, 0.012), state("released", 0.014, 0.016)};
  const std::vector<cell::StateResult> after = {state("four grasps", 0.011, 0.011), state("released", 0.009, 0.0117)};
  const auto write = [&](const std::string& name, const nlohmann::json& j) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << j.dump(2);
    return path;
  };
  const auto b = cell::read_results_json(write("before.json", cell::results_json(before)));
  const auto a = cell::read_results_json(write("after.json", cell::results_json(after)));
  REQUIRE(b.size() == 2);
  CHECK(b[1].name == "released");
  CHECK(b[1].twin_vs_truth.mean_m == Approx(0.016));
  CHECK(b[1].twin_vs_truth.samples == 1);
  const std::string table = cell::format_comparison(b, a);
  INFO(table);
  CHECK_THAT(table, Contains(" 14.0/ 56.0 ->   9.0/ 36.0"));  // released: prediction error
  CHECK_THAT(table, Contains(" 16.0/ 80.0 ->  11.7/ 58.5"));  // released: twin vs truth
  CHECK_THAT(table, Contains("mean over the states     |        12.0 ->  10.0"));
  // Without truth on the bus (a real cell) the column shows "-"; a state only one run has too.
  const auto no_truth = cell::read_results_json(write("real.json", cell::results_json({state("four grasps", 0.01, 0)})));
  CHECK(no_truth[0].twin_vs_truth.samples == 0);
  CHECK_THAT(cell::format_comparison(b, no_truth), Contains("released"));

  nlohmann::json bad = cell::results_json(before);
  bad["states"][1]["twin_vs_truth"]["mean_m"] = -1;
  CHECK_THROWS_WITH(cell::read_results_json(write("bad.json", bad)),
                    Contains("bad.json") && Contains("states[1].twin_vs_truth.mean_m"));
  bad = cell::results_json(before);
  bad["states"][0]["window_cycles"] = 1e300;  // was cast to int: undefined behaviour
  CHECK_THROWS_WITH(cell::read_results_json(write("bad.json", bad)),
                    Contains("bad.json") && Contains("states[0].window_cycles"));
  bad = cell::results_json(before);
  bad["format"] = "something else";
  CHECK_THROWS_WITH(cell::read_results_json(write("bad.json", bad)), Contains("format"));
}
