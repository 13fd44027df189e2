// camera_probe: what a cell engineer runs at start-up (and CI against the emulated device):
// opens the cameras of a cell config through the back-end registry (real and simulated
// back-ends), each wrapped in the generic frame monitor, reads until every camera delivered N
// frames (or --max-seconds passed), and prints per camera: read-status counts, frame rate, valid
// depth fraction, depth range, colour frames and health, then one machine-readable summary line.
//   camera_probe --config cell.json [--camera NAME] [--frames N] [--max-seconds S] [--dump DIR]
// --dump writes each delivered frame as DIR/<camera>_<sequence>_depth.pgm (16-bit PGM, mm) and
// _color.ppm. Exit code: 0 all cameras delivered N frames, 1 bad config or arguments, 2 otherwise.

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <thread>

#include "drivers/camera_config_json.h"
#include "drivers/camera_registry.h"
#include "drivers/monitored_depth_camera.h"
#include "drivers/pnm_image.h"
#include "sim_hw/simulated_cameras.h"

namespace {

using drivers::ReadStatus;

struct Probe {
  drivers::CameraConfig config;
  std::unique_ptr<drivers::MonitoredDepthCamera> camera;
  std::string failure;  // configure/activate failure
  std::map<ReadStatus, int> counts;
  int delivered = 0, with_color = 0;
  std::int64_t first_host_us = 0, last_host_us = 0;
  std::uint64_t valid_pixels = 0, pixels = 0;
  std::uint16_t min_mm = 65535, max_mm = 0;
};

void account(Probe& p, const drivers::DepthFrame& f, const std::string& dump_dir) {
  ++p.delivered;
  if (p.first_host_us == 0) p.first_host_us = f.host_time_us;
  p.last_host_us = f.host_time_us;
  p.pixels += f.depth_mm.size();
  for (std::uint16_t v : f.depth_mm) {
    if (v == 0) continue;
    ++p.valid_pixels;
    p.min_mm = std::min(p.min_mm, v);
    p.max_mm = std::max(p.max_mm, v);
  }
  if (!f.rgb.empty()) ++p.with_color;
  if (dump_dir.empty()) return;
  const std::string stem = dump_dir + "/" + p.config.name + "_" + std::to_string(f.sequence);
  std::string error = drivers::write_pgm16(stem + "_depth.pgm", f.depth_intrinsics.width, f.depth_intrinsics.height,
                                           f.depth_mm);
  if (error.empty() && !f.rgb.empty())
    error = drivers::write_ppm8(stem + "_color.ppm", f.color_intrinsics.width, f.color_intrinsics.height, f.rgb);
  if (!error.empty()) fmt::print(stderr, "camera_probe: {}\n", error);
}

void report(const Probe& p) {
  const drivers::CameraHealth h = p.camera ? p.camera->health() : drivers::CameraHealth{};
  fmt::print("camera {} (backend {}, uri {})\n", p.config.name, p.config.backend, p.config.uri);
  if (!p.failure.empty()) fmt::print("  FAILED: {}\n", p.failure);
  auto count = [&](ReadStatus s) { auto it = p.counts.find(s); return it == p.counts.end() ? 0 : it->second; };
  std::string reads;
  for (ReadStatus s : {ReadStatus::kFrame, ReadStatus::kTimeout, ReadStatus::kStale, ReadStatus::kFrozen,
                       ReadStatus::kCorrupt, ReadStatus::kLost, ReadStatus::kNotActive})
    reads += fmt::format("{}{} {}", reads.empty() ? "" : ", ", drivers::to_string(s), count(s));
  fmt::print("  reads: {}\n", reads);
  const double span_s = (p.last_host_us - p.first_host_us) * 1e-6;
  const double fps = p.delivered > 1 && span_s > 0 ? (p.delivered - 1) / span_s : 0.0;
  const double valid = p.pixels ? 100.0 * p.valid_pixels / p.pixels : 0.0;
  fmt::print("  frames {} ({:.1f} fps), with colour {}, dropped {}\n", p.delivered, fps, p.with_color, h.dropped);
  if (p.valid_pixels) fmt::print("  depth: valid {:.1f} %, range {}..{} mm\n", valid, p.min_mm, p.max_mm);
  else fmt::print("  depth: no valid pixel\n");
  fmt::print("  health: {}{}{}; reopened {} of {} attempts\n", drivers::to_string(h.state),
             h.message.empty() ? "" : " - ", h.message, h.reopened, h.reopen_attempts);
  fmt::print("summary camera={} frames={} fps={:.1f} valid={:.1f} min_mm={} max_mm={} timeout={} stale={} "
             "frozen={} corrupt={} lost={} dropped={} reopened={} state={}\n",
             p.config.name, p.delivered, fps, valid, p.valid_pixels ? p.min_mm : 0, p.max_mm,
             count(ReadStatus::kTimeout), count(ReadStatus::kStale), count(ReadStatus::kFrozen),
             count(ReadStatus::kCorrupt), count(ReadStatus::kLost), h.dropped, h.reopened,
             drivers::to_string(h.state));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Open the cameras of a cell config, read frames and report their health"};
  std::string config_path, only_camera, dump_dir;
  int frames = 30;
  double max_seconds = 10.0;
  app.add_option("--config", config_path, "cell config JSON (its \"cameras\" array)")->required();
  app.add_option("--camera", only_camera, "probe only this camera (name)");
  app.add_option("--frames", frames, "frames to read per camera")->check(CLI::PositiveNumber);
  app.add_option("--max-seconds", max_seconds, "give up after this long (s)")->check(CLI::PositiveNumber);
  app.add_option("--dump", dump_dir, "write each frame as PGM/PPM files into this directory");
  CLI11_PARSE(app, argc, argv);

  drivers::register_real_depth_cameras();
  sim_hw::register_simulated_depth_cameras();

  std::vector<Probe> probes;
  try {
    for (const drivers::CameraConfig& c : drivers::read_camera_configs(config_path))
      if (only_camera.empty() || c.name == only_camera) probes.emplace_back().config = c;
    if (probes.empty()) throw std::invalid_argument(config_path + ": no camera named \"" + only_camera + "\"");
    for (Probe& p : probes)
      p.camera = std::make_unique<drivers::MonitoredDepthCamera>(drivers::make_depth_camera(p.config.backend));
  } catch (const std::exception& e) {
    fmt::print(stderr, "camera_probe: {}\n", e.what());
    return 1;
  }
  for (Probe& p : probes) {
    drivers::DriverResult r = p.camera->configure(p.config);
    if (r.ok) r = p.camera->activate();
    if (!r.ok) p.failure = r.message;
  }

  // Round robin: each read waits at most the camera's read_timeout, and the drivers buffer a few
  // frames, so one thread keeps up with several 30 fps cameras.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(max_seconds);
  drivers::DepthFrame frame;
  for (;;) {
    bool pending = false;
    for (Probe& p : probes) {
      if (!p.failure.empty() || p.delivered >= frames) continue;
      pending = true;
      const ReadStatus s = p.camera->read(frame);
      ++p.counts[s];
      if (s == ReadStatus::kFrame || s == ReadStatus::kStale || s == ReadStatus::kFrozen) account(p, frame, dump_dir);
      if (s == ReadStatus::kLost) std::this_thread::sleep_for(std::chrono::milliseconds(10));  // read() does not wait
    }
    if (!pending || std::chrono::steady_clock::now() >= deadline) break;
  }
  bool all = true;
  for (Probe& p : probes) {
    report(p);
    all &= p.failure.empty() && p.delivered >= frames;
    p.camera->deactivate();
  }
  return all ? 0 : 2;
}
