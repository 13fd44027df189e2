// d415_v4l2_emulator: serves a camera of a cell config (typically backend "simulated") as an
// emulated D415 V4L2 device, so another process runs the real V4L2 back-end against it through
// the LD_PRELOAD shim (CI has no /dev/video):
//   d415_v4l2_emulator --config sim_cell.json --camera cam_left --prefix prepreg_cam_left &
//   PREPREG_V4L2_EMULATION=<printed spec> LD_PRELOAD=<libprepreg_v4l2_shim.so>
//     camera_probe --config v4l2_cell.json      (uri = the printed v4l2 uri)
// Use a real-time camera (a simulated D415 scene with "clock": "wall"): a simulated clock falls
// behind real time when rendering is slow and its frames then look stale to the reader.
// Prints "emulation <spec>" and "uri <uri>" lines at start, then publishes each frame the camera
// delivers (its faults included) until --seconds pass (0 = until killed) or SIGINT/SIGTERM.

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <thread>

#include "drivers/camera_config_json.h"
#include "drivers/camera_registry.h"
#include "sim_hw/simulated_cameras.h"
#include "sim_hw/v4l2_camera_bridge.h"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Serve a camera of a cell config as an emulated D415 V4L2 device (shared memory)"};
  std::string config_path, camera_name, prefix, depth_device = "/dev/video0", color_device = "/dev/video2";
  double seconds = 0;
  app.add_option("--config", config_path, "cell config JSON")->required();
  app.add_option("--camera", camera_name, "camera name in the config")->required();
  app.add_option("--prefix", prefix, "shm node names <prefix>_depth, <prefix>_color (default prepreg_<camera>)");
  app.add_option("--depth-device", depth_device, "device path the shim shows the depth node as");
  app.add_option("--color-device", color_device, "device path the shim shows the colour node as");
  app.add_option("--seconds", seconds, "stop after this long (s); 0 = until killed")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  if (prefix.empty()) prefix = "prepreg_" + camera_name;

  drivers::register_real_depth_cameras();
  sim_hw::register_simulated_depth_cameras();
  std::unique_ptr<drivers::DepthCamera> camera;
  std::unique_ptr<sim_hw::V4l2CameraBridge> bridge;
  int fps = 30;
  try {
    drivers::CameraConfig config;
    bool found = false;
    for (const drivers::CameraConfig& c : drivers::read_camera_configs(config_path))
      if (c.name == camera_name) config = c, found = true;
    if (!found) throw std::invalid_argument(config_path + ": no camera named \"" + camera_name + "\"");
    camera = drivers::make_depth_camera(config.backend);
    drivers::DriverResult r = camera->configure(config);
    if (r.ok) r = camera->activate();
    if (!r.ok) throw std::runtime_error(r.message);
    bridge = std::make_unique<sim_hw::V4l2CameraBridge>(*camera, config, prefix);
    fps = config.depth_mode.fps;
  } catch (const std::exception& e) {
    fmt::print(stderr, "d415_v4l2_emulator: {}\n", e.what());
    return 1;
  }
  fmt::print("emulation {}\nuri {}\n", bridge->emulation_spec(depth_device, color_device),
             bridge->v4l2_uri(depth_device, color_device));
  std::fflush(stdout);

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  // A real camera's read() waits for its next frame; a stand-in may return at once, so pace the
  // loop at the depth mode's rate as well (no extra wait when read() already took a period).
  const auto period = std::chrono::microseconds(1000000 / std::max(1, fps));
  auto next = std::chrono::steady_clock::now();
  while (!g_stop && (seconds == 0 || std::chrono::steady_clock::now() < end)) {
    bridge->pump();
    next = std::max(next + period, std::chrono::steady_clock::now() - period);
    std::this_thread::sleep_until(next);
  }
  camera->deactivate();
  fmt::print("published {} frames\n", bridge->published());
  return 0;
}
