#include "cell/bench/bench_session.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "drivers/session_recorder.h"
#include "sim_hw/sheet_scene.h"
#include "sim_hw/simulated_d415.h"
#include "twin/base/atomic_file.h"

namespace cell_bench {

sim_hw::WorldConfig bench_world_config(const std::string& cell_config_path, const std::string& world_path) {
  sim_hw::WorldConfig world = sim_hw::read_world_config(cell_config_path, world_path);
  for (sim_hw::WorldCamera& cam : world.cameras) cam.config.depth_mode.fps = cam.config.color_mode.fps = kCameraFps;
  return world;
}

bool has_session(const std::filesystem::path& dir) { return std::filesystem::exists(dir / "session.json"); }

void record_session(const sim_hw::WorldConfig& world, const sim_hw::TrueSheet& sheet,
                    const std::filesystem::path& dir, double seconds) {
  auto scene = std::make_shared<sim_hw::RenderScene>(world.static_scene);
  scene->meshes.push_back(sim_hw::sheet_scene_mesh(sheet.mesh(), sheet.positions()));
  const std::shared_ptr<const sim_hw::RenderScene> still = scene;
  // Recorded beside and renamed into place once complete: has_session never takes a recording cut
  // short (killed, crashed) for a whole one.
  std::filesystem::path partial = dir;
  partial += ".partial";
  std::filesystem::remove_all(partial);
  drivers::SessionRecorder recorder(partial);
  const auto frames = static_cast<std::uint64_t>(std::max(1.0, std::round(seconds * kCameraFps)));
  for (const sim_hw::WorldCamera& cam : world.cameras) {
    sim_hw::SimulatedD415Options options;
    options.scene = [still](double) { return still; };  // the sheet hangs still while recorded
    options.noise = cam.noise;                          // noise differs per frame: never "frozen"
    options.seed = cam.seed;
    options.clock = sim_hw::SimClock::kSimulated;
    sim_hw::SimulatedD415Camera camera(options);
    drivers::DriverResult r = camera.configure(cam.config);
    if (r.ok) r = camera.activate();
    if (!r.ok) throw std::runtime_error("recording camera " + cam.config.name + ": " + r.message);
    recorder.describe(cam.config);
    std::string error;
    const std::uint64_t got = drivers::record_frames(camera, recorder, frames, 3 * frames, &error);
    camera.deactivate();
    if (got < frames)
      throw std::runtime_error("recording camera " + cam.config.name + ": " + std::to_string(got) + " of " +
                               std::to_string(frames) + " frames recorded" + (error.empty() ? "" : ": " + error));
  }
  std::filesystem::rename(partial, dir);
  twin::sync_directory(dir.parent_path().empty() ? std::filesystem::path(".") : dir.parent_path());
}

cell::CellConfig bench_cell_config(const std::string& cell_config_path, const std::filesystem::path& session,
                                   double hz, int triangles, const std::filesystem::path& work_dir) {
  std::ifstream in(cell_config_path);
  if (!in) throw std::runtime_error(cell_config_path + ": cannot be read");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, true, false);
  const std::filesystem::path base = std::filesystem::absolute(cell_config_path).parent_path();
  // The file is written elsewhere: its relative paths must keep pointing at the examples.
  const auto absolute = [&](nlohmann::json& field) { field = (base / field.get<std::string>()).string(); };
  j["cell"]["lcm_url"] = "memq://";
  // The benchmark measures the cell on the wall, as it runs on real hardware (the fake cell's
  // config runs on the fake world's clock, which this bench has not).
  j["cell"]["clock"] = "wall";
  j["cell"]["cycle_hz"] = hz;
  absolute(j.at("twin").at("material_file"));
  if (triangles > 0) {  // else the config's own twin
    j["twin"]["sheet"]["target_triangles"] = triangles;
    j["twin"]["sheet"].erase("edge_length_m");
  }
  absolute(j.at("job").at("plan_file"));
  j["job"].erase("experiment_file");
  if (j.contains("tracker") && j["tracker"].is_string()) absolute(j["tracker"]);
  for (nlohmann::json& c : j.at("cameras")) {
    const std::string name = c.at("name").get<std::string>();
    c["backend"] = "replay";
    c["uri"] = std::filesystem::absolute(session).string() + "#" + name + "?pace=recorded&loop=1&rebase=1&live=1";
    c["depth_mode"]["fps"] = kCameraFps;
    c["color_mode"]["fps"] = kCameraFps;
  }
  twin::create_directories_durably(work_dir);
  const std::filesystem::path out = work_dir / "bench_cell.json";
  twin::write_file_atomically(out, [&](std::ostream& o) { o << j.dump(2) << "\n"; });
  return cell::read_cell_config(out.string());
}

}  // namespace cell_bench
