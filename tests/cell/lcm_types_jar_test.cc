// The lcm-spy types jar decodes what the C++ side encodes: messages encoded here are decoded by
// the jar's Java classes (as lcm-spy decodes them, fingerprint checked) and the values compared.
// Only built when the jar is (a JDK and liblcm-java are installed).
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <prepreg_lcm/sim_clock_t.hpp>
#include <string>

#include "tests/cell/cycle_messages.h"
#include "tests/support/temp_dir.h"

namespace {

template <typename T>
std::string write(const testing_support::TempDir& dir, const std::string& name, const T& msg) {
  const std::string path = (dir / name).string();
  const auto bytes = testing_support::encode_message(msg);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

}  // namespace

TEST_CASE("lcm-spy jar: the Java classes decode the C++ messages", "[monitor]") {
  testing_support::TempDir dir("lcm_jar");
  std::mt19937 rng(3);
  auto c = testing_support::make_cycle(72, 1'800'000'000'123'456, rng, 3, "cam_left");
  c.error.num_vertex_errors = 2;
  c.error.vertex_error_m = {0.25f, 0.5f};
  prepreg_lcm::sim_clock_t clock{};  // the fake world's clock, as lcm-spy shows it
  clock.utime = 1'800'000'000'500'000;
  clock.sim_us = 12'500'000;
  clock.real_time_factor = 0.5;
  clock.state = prepreg_lcm::sim_clock_t::STATE_HELD;
  clock.held_by = "cell_controller";
  const std::string command = "java -cp " PREPREG_LCM_JAR ":" PREPREG_LCM_TYPES_JAR
                              " " PREPREG_SOURCE_DIR
                              "/tests/cell/LcmTypesDecode.java"
                              " prepreg_lcm.prediction_error_t " +
                              write(dir, "error.bin", c.error) + " prepreg_lcm.cell_state_t " +
                              write(dir, "state.bin", c.state) + " prepreg_lcm.sheet_state_t " +
                              write(dir, "sheet.bin", c.observed) + " lcmtypes.lcmt_iiwa_status " +
                              write(dir, "arm.bin", c.arm) + " prepreg_lcm.sim_clock_t " +
                              write(dir, "clock.bin", clock) + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe);
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  CHECK(pclose(pipe) == 0);
  INFO(out);
  CHECK_THAT(out, Catch::Contains("type prepreg_lcm.prediction_error_t\nutime=1800000000123456\n"
                                  "cycle_id=72\nframes_utime=1800000000083456\n"));
  CHECK_THAT(out, Catch::Contains("num_compared=" + std::to_string(c.error.num_compared) + "\n"));
  CHECK_THAT(out, Catch::Contains("vertex_error_m=[0.25, 0.5]\n"));
  CHECK_THAT(out, Catch::Contains("type prepreg_lcm.cell_state_t\n"));
  CHECK_THAT(out, Catch::Contains("state=3\nreason=camera cam_left lost\n"));
  CHECK_THAT(out, Catch::Contains("type prepreg_lcm.sheet_state_t\n"));
  CHECK_THAT(out, Catch::Contains("num_vertices=9\n"));
  CHECK_THAT(out, Catch::Contains("type lcmtypes.lcmt_iiwa_status\n"));
  CHECK_THAT(out, Catch::Contains("joint_position_measured=[0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1]\n"));
  CHECK_THAT(out, Catch::Contains("type prepreg_lcm.sim_clock_t\nutime=1800000000500000\nsim_us=12500000\n"
                                  "real_time_factor=0.5\nstate=1\nheld_by=cell_controller\n"));
}
