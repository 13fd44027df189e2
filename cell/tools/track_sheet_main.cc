// track_sheet: the camera half of the cell's cycle on its own. Opens the cameras of a cell config
// (any back-end: v4l2, openni2, replay of a recorded session, simulated), each behind the generic
// frame monitor; each cycle reads one frame per camera, tracks the sheet from a predicted mesh
// and prints the cameras that contributed, coverage, the prediction error (Algorithm 1) and the
// cycle's time; at the end the median and p99 time per cycle. This is how a recording from a
// real cell is replayed into the tracker, and the tracker benchmark on recorded data.
//   track_sheet --config cell.json --prediction sheet.ply [--tracker tracker.json]
//               [--cycles N] [--out DIR] [--record DIR]
// --out writes DIR/tracked_<cycle>.ply (tracked surface; per-vertex error_m = |tracked -
// predicted| and observed 0/1). --record writes the frames read as a camera session (replay with
// back-end "replay"). Exit code: 0 every cycle tracked, 1 bad input, 2 some cycle did not.

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "drivers/camera_config_json.h"
#include "drivers/camera_registry.h"
#include "drivers/monitored_depth_camera.h"
#include "drivers/session_recorder.h"
#include "sim_hw/simulated_cameras.h"
#include "tracking/sheet_tracker.h"
#include "tracking/tracker_config_json.h"
#include "twin/base/atomic_file.h"
#include "twin/mesh/mesh_io.h"

namespace {

struct OpenCamera {
  drivers::CameraConfig config;
  std::unique_ptr<drivers::MonitoredDepthCamera> camera;
};

tracking::SurfaceMesh to_tracking_mesh(const twin::SurfaceMesh& mesh) {
  tracking::SurfaceMesh out;
  out.vertices_m = mesh.positions;
  for (const auto& t : mesh.triangles) out.triangles.emplace_back(t[0], t[1], t[2]);
  for (const auto& uv : mesh.uv) out.rest_uv_m.push_back(uv);
  return out;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))];
}

void write_tracked(const std::filesystem::path& path, const tracking::SurfaceMesh& prediction,
                   const tracking::TrackResult& r) {
  twin::SurfaceMesh mesh;
  mesh.positions = r.vertices_m;
  for (const auto& t : prediction.triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  twin::VertexScalar error{"error_m", r.prediction_error.per_vertex_norm_m};
  twin::VertexScalar observed{"observed", {}};
  for (auto o : r.vertex_observed) observed.values.push_back(o);
  if (error.values.size() != mesh.positions.size()) error.values.assign(mesh.positions.size(), 0.0);
  twin::write_ply(path, mesh, {error, observed});
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Track the held sheet from the cell's cameras against a predicted mesh"};
  std::string config_path, prediction_path, tracker_path, out_dir, record_dir;
  int cycles = 30;
  app.add_option("--config", config_path, "cell config with a \"cameras\" array")->required();
  app.add_option("--prediction", prediction_path, "predicted sheet mesh (PLY/OBJ, cell frame, m)")->required();
  app.add_option("--tracker", tracker_path, "tracker config JSON (default: built-in defaults)");
  app.add_option("--cycles", cycles, "cycles to run")->check(CLI::PositiveNumber);
  app.add_option("--out", out_dir, "write the tracked surface of each cycle as PLY here");
  app.add_option("--record", record_dir, "record the frames read as a camera session here");
  CLI11_PARSE(app, argc, argv);

  std::vector<OpenCamera> cameras;
  tracking::SurfaceMesh prediction;
  tracking::TrackerConfig tracker_config;
  std::optional<drivers::SessionRecorder> recorder;
  try {
    drivers::register_real_depth_cameras();
    sim_hw::register_simulated_depth_cameras();
    prediction = to_tracking_mesh(twin::read_surface_mesh(prediction_path));
    if (const std::string why = tracking::validate_mesh(prediction); !why.empty()) {
      throw std::runtime_error(prediction_path + ": " + why);
    }
    if (!tracker_path.empty()) tracker_config = tracking::load_tracker_config(tracker_path);
    for (const auto& config : drivers::read_camera_configs(config_path)) {
      OpenCamera c{config, std::make_unique<drivers::MonitoredDepthCamera>(
                               drivers::make_depth_camera(config.backend))};
      if (auto r = c.camera->configure(config); !r.ok) throw std::runtime_error(r.message);
      if (auto r = c.camera->activate(); !r.ok) throw std::runtime_error(r.message);
      cameras.push_back(std::move(c));
    }
    if (!out_dir.empty()) twin::create_directories_durably(out_dir);
    if (!record_dir.empty()) {
      recorder.emplace(record_dir);
      for (const auto& c : cameras) recorder->describe(c.config);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "track_sheet: {}\n", e.what());
    return 1;
  }

  tracking::SheetTracker tracker(tracker_config);
  std::vector<double> cycle_ms;
  int failed = 0;
  // Prediction error twice: Algorithm 1 (to the nearest predicted vertex, the paper's figure) and
  // to the predicted surface (free of the mesh's vertex spacing).
  fmt::print("cycle  cameras  coverage  alg1 mean/max mm  surface mean/max mm  points  ms    status\n");
  for (int cycle = 0; cycle < cycles; ++cycle) {
    std::vector<drivers::DepthFrame> frames;
    std::string camera_notes;
    for (auto& c : cameras) {
      drivers::DepthFrame frame;
      const drivers::ReadStatus status = c.camera->read(frame);
      if (status != drivers::ReadStatus::kFrame) {
        camera_notes += fmt::format(" {}:{}", c.config.name, drivers::to_string(status));
        continue;  // stale, frozen, corrupt or missing frames are not tracked
      }
      if (recorder) {
        if (auto r = recorder->append(frame); !r.ok) camera_notes += " record:" + r.message;
      }
      frames.push_back(std::move(frame));
    }
    const tracking::TrackResult r = tracker.track(frames, prediction);
    cycle_ms.push_back(r.times.total_ms);
    const bool ok = r.status == tracking::TrackStatus::kOk;
    if (!ok) ++failed;
    const tracking::PredictionError& e = r.prediction_error;
    fmt::print("{:5d}  {:7d}  {:8.3f}  {:7.2f} {:8.2f}  {:8.2f} {:10.2f}  {:6d}  {:5.1f} {}{}\n", cycle,
               r.cameras_used.size(), r.coverage.fraction, 1e3 * e.mean_m, 1e3 * e.max_m,
               1e3 * e.surface_mean_m, 1e3 * e.surface_max_m, r.resampled_points, r.times.total_ms,
               tracking::to_string(r.status), camera_notes);
    if (!out_dir.empty() && ok) {
      write_tracked(std::filesystem::path(out_dir) / fmt::format("tracked_{:04d}.ply", cycle), prediction, r);
    }
  }
  for (auto& c : cameras) c.camera->deactivate();
  fmt::print("track_sheet: {} cycles, {} tracked, cycle median {:.1f} ms, p99 {:.1f} ms\n", cycles,
             cycles - failed, percentile(cycle_ms, 0.5), percentile(cycle_ms, 0.99));
  return failed == 0 ? 0 : 2;
}
