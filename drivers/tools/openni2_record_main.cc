// openni2_record: records an OpenNI2 device (a D415 through a RealSense OpenNI2 driver, or a
// simulated one through libprepreg_openni2_sim) into an .oni file, replayable with the "openni2"
// back-end (CameraConfig::uri = the file).
//   openni2_record --uri any --out cell_left.oni --frames 300 --depth 848x480@30 --color 848x480@30

#include <CLI/CLI.hpp>
#include <cstdio>
#include <regex>

#include <fmt/format.h>

#include "drivers/openni2_recorder.h"

namespace {

// "848x480@30" -> mode; throws CLI::ValidationError naming the option otherwise.
drivers::StreamMode parse_mode(const std::string& option, const std::string& text) {
  std::smatch m;
  if (!std::regex_match(text, m, std::regex(R"((\d+)x(\d+)@(\d+))"))) {
    throw CLI::ValidationError(option, "\"" + text + "\" is not WIDTHxHEIGHT@FPS, e.g. 848x480@30");
  }
  return {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3])};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Record an OpenNI2 device session to an .oni file"};
  drivers::CameraConfig config;
  std::string out, depth = "848x480@30", color = "848x480@30";
  int frames = 300, timeout_ms = 1000;
  app.add_option("--uri", config.uri, "OpenNI2 device URI, or \"any\"")->default_val("any");
  app.add_option("--serial", config.serial, "expected serial number (checked when given)");
  app.add_option("--out", out, ".oni file to write")->required();
  app.add_option("--frames", frames, "depth frames to record")->check(CLI::PositiveNumber);
  app.add_option("--depth", depth, "depth mode WIDTHxHEIGHT@FPS");
  app.add_option("--color", color, "colour mode WIDTHxHEIGHT@FPS (used when the device has colour)");
  app.add_option("--timeout-ms", timeout_ms, "give up when no frame comes for this long (ms)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    config.depth_mode = parse_mode("--depth", depth);
    config.color_mode = parse_mode("--color", color);
  } catch (const CLI::Error& e) {
    return app.exit(e);
  }
  config.read_timeout = std::chrono::milliseconds(timeout_ms);
  config.name = config.uri;  // names the device in error messages
  drivers::OpenNI2RecordingStats stats;
  const drivers::DriverResult result = drivers::record_openni2_session(config, out, frames, &stats);
  if (!result.ok) {
    std::fprintf(stderr, "openni2_record: %s\n", result.message.c_str());
    return 2;
  }
  fmt::print("openni2_record: {} depth and {} colour frames from {} -> {}\n", stats.depth_frames,
             stats.color_frames, config.uri, out);
  return 0;
}
