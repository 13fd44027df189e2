// Cell config and experiment file reading, and the watchdog's rules on their own.
#include <catch2/catch.hpp>

#include "cell/cell_config.h"
#include "cell/experiment_file.h"
#include "cell/watchdog.h"
#include "tests/cell/cell_rig.h"

using Catch::Matchers::Contains;

TEST_CASE("the fake cell config reads, with paths relative to its folder", "[cell]") {
  const std::string examples = std::string(PREPREG_SOURCE_DIR) + "/cell/examples/";
  const cell::CellConfig c = cell::read_cell_config(examples + "fake_cell.json");
  CHECK(c.cameras.size() == 3);
  CHECK(c.hardware.arms.size() == 3);
  CHECK(c.cell.cycle_hz == 10);
  CHECK(c.cell.min_cameras == 2);
  CHECK(c.material_file == examples + "composite_identified.json");
  CHECK(c.plan_file == examples + "four_grasp_plan.json");
  CHECK(c.experiment_file == examples + "four_grasp_experiment.json");
  CHECK_FALSE(c.sheet_placement_given);
  CHECK(c.cell.twin_priority == cell::WorkerPriority::kNormal);  // the default
  CHECK(c.cell.clock == drivers::ClockSource::kSim);  // the fake cell runs on the world's clock
  CHECK(c.cell.twin_lockstep);                        // and so steps its twin in lockstep
  CHECK(c.learning.diagnose);  // the default
  CHECK(c.learning.diagnosis.noise_mm == 3.4);
  CHECK(c.learning.diagnosis.effects == cell::learning::kCellEffects);
  const cell::Experiment e = cell::read_experiment(c.experiment_file);
  REQUIRE(e.states.size() == 4);
  CHECK(e.states[1].actions.at(0).kind == cell::ExperimentAction::Kind::kRelease);
  CHECK(e.states[1].actions.at(0).gripper == "MANUAL");
  CHECK(e.states[2].actions.at(0).kind == cell::ExperimentAction::Kind::kMove);
  CHECK(e.states[2].actions.at(0).to_m.z() == Approx(1.15));
  CHECK(e.states[3].settle_s == 6.0);
}

TEST_CASE("cell.twin_priority reads idle and normal", "[cell]") {
  testing_support::TempDir dir("cell_config");
  cell_test::RigFiles f = cell_test::default_files();
  f.config["cell"]["twin_priority"] = "normal";
  CHECK(cell::read_cell_config(cell_test::write_files(dir, f)).cell.twin_priority == cell::WorkerPriority::kNormal);
  f.config["cell"]["twin_priority"] = "idle";
  CHECK(cell::read_cell_config(cell_test::write_files(dir, f)).cell.twin_priority == cell::WorkerPriority::kIdle);
}

TEST_CASE("cell.clock is the wall by default, sim on request with the twin in lockstep", "[cell]") {
  testing_support::TempDir dir("cell_config");
  cell_test::RigFiles f = cell_test::default_files();
  f.config["cell"].erase("clock");
  const cell::CellConfig wall = cell::read_cell_config(cell_test::write_files(dir, f));
  CHECK(wall.cell.clock == drivers::ClockSource::kWall);
  CHECK_FALSE(wall.cell.twin_lockstep);
  f.config["cell"]["clock"] = "sim";
  f.config["cell"]["sim_clock_timeout_s"] = 2.5;
  const cell::CellConfig sim = cell::read_cell_config(cell_test::write_files(dir, f));
  CHECK(sim.cell.clock == drivers::ClockSource::kSim);
  CHECK(sim.cell.sim_clock_timeout_s == 2.5);
  CHECK(sim.cell.twin_lockstep);
  f.config["cell"]["twin_lockstep"] = false;
  CHECK_THROWS_WITH(cell::read_cell_config(cell_test::write_files(dir, f)),
                    Contains("cell.twin_lockstep") && Contains("\"sim\""));
  f.config["cell"].erase("twin_lockstep");
  f.config["cell"]["clock"] = "gps";
  CHECK_THROWS_WITH(cell::read_cell_config(cell_test::write_files(dir, f)),
                    Contains("cell.clock") && Contains("\"wall\"") && Contains("\"sim\""));
}

TEST_CASE("cell.twin_background_factorization is on by default and reads true and false", "[cell]") {
  testing_support::TempDir dir("cell_config");
  cell_test::RigFiles f = cell_test::default_files();
  CHECK(cell::read_cell_config(cell_test::write_files(dir, f)).cell.twin_background_factorization);
  f.config["cell"]["twin_background_factorization"] = false;
  CHECK_FALSE(cell::read_cell_config(cell_test::write_files(dir, f)).cell.twin_background_factorization);
  f.config["cell"]["twin_background_factorization"] = "yes";
  CHECK_THROWS_WITH(cell::read_cell_config(cell_test::write_files(dir, f)),
                    Contains("cell.twin_background_factorization") && Contains("true or false"));
}

TEST_CASE("the learning section reads the diagnosis's settings and names a bad one", "[cell]") {
  testing_support::TempDir dir("cell_config");
  cell_test::RigFiles f = cell_test::default_files();
  f.config["learning"] = {{"diagnosis_effects", {"clamp_grip", "clamp_slip"}},
                          {"diagnosis_noise_mm", 2.5},
                          {"diagnosis_max_evaluations", 7}};
  const cell::CellConfig c = cell::read_cell_config(cell_test::write_files(dir, f));
  CHECK(c.learning.diagnosis.effects == "clamp_grip,clamp_slip");
  CHECK(c.learning.diagnosis.noise_mm == 2.5);
  CHECK(c.learning.diagnosis.base_evaluations == 7);
  CHECK(c.learning.diagnosis.refit_evaluations == 7);
  f.config["learning"] = {{"diagnosis_effects", {"clamp_grip", "glue"}}};
  CHECK_THROWS_WITH(cell::read_cell_config(cell_test::write_files(dir, f)),
                    Contains("learning.diagnosis_effects") && Contains("glue"));
  f.config["learning"] = {{"diagnosis_noise_mm", -1}};
  CHECK_THROWS_WITH(cell::read_cell_config(cell_test::write_files(dir, f)), Contains("learning.diagnosis_noise_mm"));
  f.config["learning"] = {{"record_states", false}, {"calibrate", false}, {"follow_branches", false}};
  CHECK_THROWS_WITH(cell::read_cell_config(cell_test::write_files(dir, f)),
                    Contains("learning.diagnose") && Contains("record_states"));
}

TEST_CASE("cell config errors name the file and the field", "[cell]") {
  testing_support::TempDir dir("cell_config");
  cell_test::RigFiles f = cell_test::default_files();
  SECTION("unknown key in cell") {
    f.config["cell"]["cycle_rate"] = 10;
    const std::string path = cell_test::write_files(dir, f);
    CHECK_THROWS_WITH(cell::read_cell_config(path), Contains("cell.json") && Contains("cycle_rate"));
  }
  SECTION("negative cycle rate") {
    f.config["cell"]["cycle_hz"] = -1;
    const std::string path = cell_test::write_files(dir, f);
    CHECK_THROWS_WITH(cell::read_cell_config(path), Contains("cell.cycle_hz"));
  }
  SECTION("missing plan") {
    f.config["job"].erase("plan_file");
    const std::string path = cell_test::write_files(dir, f);
    CHECK_THROWS_WITH(cell::read_cell_config(path), Contains("job.plan_file") && Contains("missing"));
  }
  SECTION("more cameras required than configured") {
    f.config["cell"]["min_cameras"] = 4;
    const std::string path = cell_test::write_files(dir, f);
    CHECK_THROWS_WITH(cell::read_cell_config(path), Contains("min_cameras"));
  }
  SECTION("twin priority not one of idle, normal") {
    f.config["cell"]["twin_priority"] = "low";
    const std::string path = cell_test::write_files(dir, f);
    CHECK_THROWS_WITH(cell::read_cell_config(path), Contains("cell.twin_priority") && Contains("\"idle\" or \"normal\""));
  }
  SECTION("move speed above the experiment's limit") {
    f.config["cell"]["move_speed_m_s"] = 0.2;
    const std::string path = cell_test::write_files(dir, f);
    CHECK_THROWS_WITH(cell::read_cell_config(path), Contains("move_speed_m_s"));
  }
}

TEST_CASE("experiment file errors name the field", "[cell]") {
  testing_support::TempDir dir("cell_experiment");
  testing_support::write_file(dir / "e.json", R"({"states": [{"name": "a", "actions": [{"lift": "LEFT"}]}]})");
  CHECK_THROWS_WITH(cell::read_experiment((dir / "e.json").string()), Contains("states[0].actions[0]"));
  testing_support::write_file(dir / "e.json", R"({"states": [{"name": "a", "actions": [{"move": "LEFT"}]}]})");
  CHECK_THROWS_WITH(cell::read_experiment((dir / "e.json").string()), Contains("to_m"));
}

TEST_CASE("watchdog: cameras, twin and arms decide the state", "[cell]") {
  cell::WatchdogInputs in;
  in.cameras = 3;
  in.min_cameras = 2;
  in.robot_status_timeout_ms = 250;
  CHECK(cell::judge(in).state == cell::CellState::kRunning);
  CHECK(cell::judge(in).reason.empty());

  in.lost_cameras = {"cam_left (lost)"};
  auto v = cell::judge(in);
  CHECK(v.state == cell::CellState::kDegraded);
  CHECK_THAT(v.reason, Contains("cam_left"));
  CHECK(cell::may_command(v.state));

  in.lost_cameras.push_back("cam_right (timeout)");
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kSafeHold);
  CHECK_THAT(v.reason, Contains("1 of 3 cameras") && Contains("cam_right"));
  CHECK_FALSE(cell::may_command(v.state));

  in.lost_cameras.clear();
  in.twin_ok = false;
  in.twin_problem = "twin step gave non-finite positions";
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kSafeHold);
  CHECK_THAT(v.reason, Contains("twin failure: twin step gave non-finite"));

  in.twin_ok = true;
  in.stale_arms = {"CENTER"};
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kSafeHold);
  CHECK_THAT(v.reason, Contains("no arm status within 250 ms from CENTER"));
  CHECK_FALSE(v.robots_ok);

  // On the simulation clock, a clock that fell silent (the world gone) holds the cell safe.
  in.stale_arms.clear();
  in.clock_problem = "simulation clock: no SIM_CLOCK for 5.0 s (is the fake world running?)";
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kSafeHold);
  CHECK_THAT(v.reason, Contains("no SIM_CLOCK"));
  in.clock_problem.clear();
  in.stale_arms = {"CENTER"};

  // Cameras that disagree degrade the cell (tracking goes on, the engineer is told which pair);
  // a cause for SAFE_HOLD still wins.
  const std::string disagree = "calibration check: cameras cam_front and cam_left disagree";
  in.calibration_problem = disagree;
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kSafeHold);
  in.stale_arms.clear();
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kDegraded);
  CHECK(v.reason == disagree);
  CHECK(cell::may_command(v.state));
  in.lost_cameras = {"cam_right (lost)"};
  v = cell::judge(in);
  CHECK(v.state == cell::CellState::kDegraded);
  CHECK_THAT(v.reason, Contains("lost cam_right") && Contains(disagree));
}
