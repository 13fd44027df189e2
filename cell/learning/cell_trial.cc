#include "cell/learning/cell_trial.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "twin/base/atomic_file.h"
#include "twin/mesh/mesh_io.h"

namespace cell::learning {
namespace fs = std::filesystem;

twin::Trial cell_trial(const std::vector<SettledObservation>& states, const twin::SheetMesh& mesh,
                       const twin::GraspPlan& plan, const twin::Material& material, const std::string& mesh_file) {
  if (states.empty()) throw std::invalid_argument("cell trial: no settled state to make a trial of");
  if (!material.thickness_m) {
    throw std::invalid_argument(fmt::format("cell trial: material '{}' has no thickness_m (a trial needs one)",
                                            material.name));
  }
  twin::Trial t;
  t.material_name = material.name;
  t.sheet.mesh_file = mesh_file;
  t.thickness_m = *material.thickness_m;
  t.surface_density_kg_m2 = material.surface_density_kg_m2;
  t.marker_uv_m = mesh.rest_uv;
  t.clamps = plan.clamp_specs();
  double previous_time_s = -1e300;
  for (std::size_t k = 0; k < states.size(); ++k) {
    const SettledObservation& s = states[k];
    if (static_cast<int>(s.vertices_m.size()) != mesh.vertex_count() || s.grasp_positions_m.size() != plan.grasps.size() ||
        s.engaged.size() != plan.grasps.size()) {
      throw std::invalid_argument(fmt::format(
          "cell trial: state {} has {} vertices and {} grasps; the twin's mesh has {} vertices and the plan {} grasps",
          k + 1, s.vertices_m.size(), s.grasp_positions_m.size(), mesh.vertex_count(), plan.grasps.size()));
    }
    twin::TrialStage stage;
    stage.id = fmt::format("s{}", k + 1);
    stage.time_s = s.time_s;
    // The trial format wants the move between the previous stage's scan and this one's.
    stage.clamps_moved_at_s = std::clamp(s.moved_at_s, std::min(previous_time_s, s.time_s), s.time_s);
    previous_time_s = s.time_s;
    for (std::size_t g = 0; g < plan.grasps.size(); ++g) {
      twin::ClampPose pose;
      pose.position_m = s.grasp_positions_m[g];
      pose.engaged = s.engaged[g] != 0;
      stage.poses.push_back(pose);
    }
    stage.observed.markers_m = s.vertices_m;
    stage.markers_file = stage.id + ".xyz";
    t.stages.push_back(std::move(stage));
  }
  return t;
}

twin::Trial write_cell_trial(const std::string& directory, const std::vector<SettledObservation>& states,
                             const twin::SheetMesh& mesh, const twin::GraspPlan& plan,
                             const twin::Material& material) {
  const fs::path dir(directory);
  const twin::Trial trial = cell_trial(states, mesh, plan, material, (fs::absolute(dir) / "sheet.obj").string());
  twin::create_directories_durably(dir);
  twin::SurfaceMesh flat;
  for (const twin::Vec2& uv : mesh.rest_uv) flat.positions.emplace_back(uv.x(), uv.y(), 0.0);
  flat.triangles = mesh.triangles;
  twin::write_obj(dir / "sheet.obj", flat);
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < states.size(); ++k) {
    const SettledObservation& s = states[k];
    // Fake hardware: the true sheet beside what was seen (not part of the trial format).
    std::string truth_file;
    if (!s.truth_m.empty()) {
      twin::create_directories_durably(dir / "truth");
      truth_file = "truth/" + trial.stages[k].id + ".xyz";
      twin::write_xyz_file((dir / truth_file).string(), s.truth_m);
    }
    rows.push_back({{"stage", trial.stages[k].id},
                    {"truth_file", truth_file.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(truth_file)},
                    {"cycles", s.cycles},
                    {"first_cycle", s.first_cycle},
                    {"last_cycle", s.last_cycle},
                    {"coverage", s.coverage},
                    {"cycle_noise_m", s.cycle_noise_m},
                    {"mean_noise_m", s.mean_noise_m},
                    {"drift_m", s.drift_m}});
  }
  twin::write_file_atomically(dir / "observations.json", [&](std::ostream& out) {
    out << nlohmann::ordered_json{{"source", "cell settled states (cell/learning/settled_state.h)"}, {"stages", rows}}
               .dump(2)
        << "\n";
  });
  twin::write_trial(trial, directory);  // trial.json last: it names only files already written
  return twin::read_trial(directory);
}

std::string cell_trial_problem(const twin::SheetPlacement& placement) {
  if (placement.rotation.isApprox(twin::Mat3::Identity(), 1e-9)) return "";
  return "the cell's ply lies rotated, so its twin holds the clamps turned; the trial's stages are solved with "
         "level jaws (the trial format has no jaw orientation)";
}

}  // namespace cell::learning
