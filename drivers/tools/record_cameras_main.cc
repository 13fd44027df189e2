// record_cameras: records frames from depth cameras into a session directory (format:
// drivers/camera_session.h) for replay in CI and benchmarks. Cameras are named on the command
// line as NAME=BACKEND:URI with the back-ends drivers/ provides (v4l2, openni2, replay, as
// registered); each loop reads every camera once, until each has --frames frames or
// --max-seconds passed.
//
//   record_cameras --out run1 --frames 300 --camera cam_left=v4l2:/dev/video2,/dev/video4
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "drivers/camera_registry.h"
#include "drivers/session_recorder.h"

namespace {

// "WxH@FPS" -> mode; "none" -> width 0 (no colour stream).
drivers::StreamMode parse_mode(const std::string& text) {
  if (text == "none") return {0, 0, 0};
  drivers::StreamMode m;
  char x = 0, at = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c%d", &m.width, &x, &m.height, &at, &m.fps) != 5 || x != 'x' || at != '@' ||
      m.width <= 0 || m.height <= 0 || m.fps <= 0) {
    throw CLI::ValidationError("mode", "'" + text + "' must be WIDTHxHEIGHT@FPS, e.g. 848x480@30");
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Record depth-camera frames into a session directory (session.json + PGM/PPM frames)."};
  std::string out;
  std::vector<std::string> cameras;
  std::uint64_t frames = 100;
  double max_seconds = 60.0;
  std::string depth_mode = "848x480@30", color_mode = "848x480@30";
  app.add_option("--out", out, "new session directory (must not hold a session yet)")->required();
  app.add_option("--camera", cameras, "NAME=BACKEND:URI, repeatable")->required();
  app.add_option("--frames", frames, "frames to record per camera")->check(CLI::PositiveNumber);
  app.add_option("--max-seconds", max_seconds, "stop after this many seconds")->check(CLI::PositiveNumber);
  app.add_option("--depth-mode", depth_mode, "WIDTHxHEIGHT@FPS");
  app.add_option("--color-mode", color_mode, "WIDTHxHEIGHT@FPS or none");
  CLI11_PARSE(app, argc, argv);

  drivers::register_real_depth_cameras();
  std::vector<std::unique_ptr<drivers::DepthCamera>> opened;
  std::vector<std::string> names;
  try {
    drivers::SessionRecorder recorder(out);
    for (const std::string& spec : cameras) {
      const auto eq = spec.find('='), colon = spec.find(':', eq == std::string::npos ? 0 : eq);
      if (eq == std::string::npos || colon == std::string::npos || eq == 0) {
        fmt::print(stderr, "--camera '{}': expected NAME=BACKEND:URI\n", spec);
        return 2;
      }
      drivers::CameraConfig config;
      config.name = spec.substr(0, eq);
      config.backend = spec.substr(eq + 1, colon - eq - 1);
      config.uri = spec.substr(colon + 1);
      config.depth_mode = parse_mode(depth_mode);
      config.color_mode = parse_mode(color_mode);
      auto cam = drivers::make_depth_camera(config.backend);  // throws naming the known back-ends
      if (const auto r = cam->configure(config); !r.ok) {
        fmt::print(stderr, "camera '{}': configure failed: {}\n", config.name, r.message);
        return 1;
      }
      if (const auto r = cam->activate(); !r.ok) {
        fmt::print(stderr, "camera '{}': activate failed: {}\n", config.name, r.message);
        return 1;
      }
      recorder.describe(config);
      opened.push_back(std::move(cam));
      names.push_back(config.name);
    }
    std::map<std::string, std::map<std::string, int>> statuses;
    const auto stop = std::chrono::steady_clock::now() + std::chrono::duration<double>(max_seconds);
    drivers::DepthFrame frame;
    bool more = true;
    while (more && std::chrono::steady_clock::now() < stop) {
      more = false;
      for (std::size_t i = 0; i < opened.size(); ++i) {
        if (recorder.frames(names[i]) >= frames) continue;
        more = true;
        const drivers::ReadStatus s = opened[i]->read(frame);
        ++statuses[names[i]][drivers::to_string(s)];
        if (s != drivers::ReadStatus::kFrame && s != drivers::ReadStatus::kStale && s != drivers::ReadStatus::kFrozen) {
          continue;
        }
        frame.camera = names[i];
        if (const auto r = recorder.append(frame); !r.ok) {
          fmt::print(stderr, "recording failed: {}\n", r.message);
          return 1;
        }
      }
    }
    for (std::size_t i = 0; i < opened.size(); ++i) {
      opened[i]->deactivate();
      std::string counts;
      for (const auto& [status, n] : statuses[names[i]]) counts += fmt::format(" {}={}", status, n);
      fmt::print("{}: {} frames recorded; reads:{}\n", names[i], recorder.frames(names[i]), counts);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "record_cameras: {}\n", e.what());
    return 1;
  }
  return 0;
}
