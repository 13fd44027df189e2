// Writing a trial directory (trial.json and the stages' observation files); see trial.h.

#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "twin/base/atomic_file.h"
#include "twin/mesh/mesh_io.h"
#include "twin/mesh/mesh_io_internal.h"
#include "twin/trials/trial.h"
#include "twin/trials/trial_internal.h"

namespace twin {
namespace {

namespace fs = std::filesystem;
using ordered_json = nlohmann::ordered_json;
using trial_internal::describe_uv;
using trial_internal::resolve;

ordered_json uv_json(const Vec2& v) { return ordered_json::array({v.x(), v.y()}); }

// The mesh path as trial.json should hold it: relative when the mesh is inside the trial
// directory (so the directory can move), absolute otherwise.
std::string mesh_file_for(const std::string& mesh_file, const fs::path& directory) {
  const fs::path relative =
      fs::absolute(mesh_file).lexically_normal().lexically_relative(fs::absolute(directory).lexically_normal());
  const bool inside = !relative.empty() && *relative.begin() != "..";
  return inside ? relative.string() : fs::absolute(mesh_file).string();
}

// A grid's spacing along an axis with a single marker is not determined by the markers; any
// positive value describes the same markers, so the other axis's (or 1 m) is used.
ordered_json grid_json(const Trial& t) {
  const int rows = *t.marker_grid_rows, cols = *t.marker_grid_cols;
  if (rows < 1 || cols < 1 || static_cast<std::size_t>(rows) * cols != t.marker_uv_m.size()) {
    throw std::invalid_argument(fmt::format("write_trial: a {} x {} marker grid does not match {} markers",
                                            rows, cols, t.marker_uv_m.size()));
  }
  const Vec2 origin = t.marker_uv_m.front();
  double du = cols > 1 ? (t.marker_uv_m[cols - 1].x() - origin.x()) / (cols - 1) : 0.0;
  double dv = rows > 1 ? (t.marker_uv_m[(rows - 1) * cols].y() - origin.y()) / (rows - 1) : 0.0;
  if (cols == 1) du = rows > 1 ? dv : 1.0;
  if (rows == 1) dv = cols > 1 ? du : 1.0;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const Vec2 expected = origin + Vec2(c * du, r * dv);
      if ((t.marker_uv_m[r * cols + c] - expected).norm() > 1e-9 * (1.0 + expected.norm())) {
        throw std::invalid_argument(fmt::format(
            "write_trial: marker {} at {} is not on the {} x {} grid the trial claims", r * cols + c,
            describe_uv(t.marker_uv_m[r * cols + c]), rows, cols));
      }
    }
  }
  return {{"rows", rows}, {"cols", cols}, {"spacing_m", {du, dv}}, {"origin_m", uv_json(origin)}};
}

ordered_json markers_json(const Trial& t) {
  if (t.marker_grid_rows.has_value() != t.marker_grid_cols.has_value()) {
    throw std::invalid_argument("write_trial: marker_grid_rows and marker_grid_cols go together");
  }
  if (t.marker_grid_rows) return {{"grid", grid_json(t)}};
  ordered_json list = ordered_json::array();
  for (const Vec2& uv : t.marker_uv_m) list.push_back(uv_json(uv));
  return {{"list_m", list}};
}

ordered_json stage_clamps_json(const Trial& t, const TrialStage& stage) {
  if (stage.poses.size() != t.clamps.size()) {
    throw std::invalid_argument(fmt::format("write_trial: stage '{}' has {} clamp poses for {} clamps",
                                            stage.id, stage.poses.size(), t.clamps.size()));
  }
  ordered_json clamps = ordered_json::object();
  for (std::size_t i = 0; i < t.clamps.size(); ++i) {
    const ClampPose& p = stage.poses[i];
    clamps[t.clamps[i].id] = p.engaged ? ordered_json::array({p.position_m.x(), p.position_m.y(),
                                                              p.position_m.z()})
                                       : ordered_json("released");
  }
  return clamps;
}

// The file a stage's observation goes to: as named, or "<id>.xyz" / "<id>_cloud.xyz".
std::string observation_file_name(const TrialStage& stage) {
  if (stage.observed.has_markers()) return stage.markers_file.empty() ? stage.id + ".xyz" : stage.markers_file;
  return stage.cloud_file.empty() ? stage.id + "_cloud.xyz" : stage.cloud_file;
}

ordered_json stage_json(const Trial& t, const TrialStage& stage) {
  if (stage.observed.has_markers() == !stage.observed.cloud_m.empty()) {
    throw std::invalid_argument("write_trial: stage '" + stage.id +
                                "' must be observed by markers or by a cloud, exactly one of them");
  }
  if (stage.observed.has_markers() && stage.observed.markers_m.size() != t.marker_uv_m.size()) {
    throw std::invalid_argument(fmt::format("write_trial: stage '{}' has {} marker positions for {} markers",
                                            stage.id, stage.observed.markers_m.size(), t.marker_uv_m.size()));
  }
  if (stage.clamps_moved_at_s && !(stage.time_s && *stage.clamps_moved_at_s <= *stage.time_s)) {
    throw std::invalid_argument(fmt::format("write_trial: stage '{}' has clamps_moved_at_s without a "
                                            "time_s at or after it", stage.id));
  }
  ordered_json j;
  j["id"] = stage.id;
  if (stage.time_s) j["time_s"] = *stage.time_s;
  if (stage.clamps_moved_at_s) j["clamps_moved_at_s"] = *stage.clamps_moved_at_s;
  j["clamps"] = stage_clamps_json(t, stage);
  j[stage.observed.has_markers() ? "markers_file" : "cloud_file"] = observation_file_name(stage);
  if (!stage.scan_file.empty()) j["scan_file"] = stage.scan_file;
  return j;
}

ordered_json trial_json(const Trial& t, const fs::path& directory) {
  ordered_json j;
  j["material"] = t.material_name;
  if (t.sheet.is_rectangle()) {
    j["sheet"] = {{"width_m", t.sheet.width_m}, {"height_m", t.sheet.height_m}};
  } else {
    j["sheet"] = {{"mesh_file", mesh_file_for(t.sheet.mesh_file, directory)}};
  }
  j["thickness_m"] = t.thickness_m;
  if (t.mass_kg) j["mass_kg"] = *t.mass_kg;
  if (t.surface_density_kg_m2) j["surface_density_kg_m2"] = *t.surface_density_kg_m2;
  if (!t.marker_uv_m.empty()) j["markers"] = markers_json(t);
  ordered_json clamps = ordered_json::array();
  for (const ClampSpec& c : t.clamps) {
    clamps.push_back({{"id", c.id}, {"material_point_m", uv_json(c.material_point_m)},
                      {"grip_radius_m", c.grip_radius_m}});
  }
  j["clamps"] = clamps;
  ordered_json stages = ordered_json::array();
  for (const TrialStage& stage : t.stages) stages.push_back(stage_json(t, stage));
  j["stages"] = stages;
  return j;
}

void write_observation(const TrialStage& stage, const fs::path& directory) {
  const fs::path path = resolve(directory, observation_file_name(stage));
  if (stage.observed.has_markers()) return write_xyz_file(path.string(), stage.observed.markers_m);
  const std::string ext = internal::lower_extension(path);
  if (ext == ".ply" || ext == ".obj") {
    SurfaceMesh points;  // vertices only: a cloud has no faces
    points.positions = stage.observed.cloud_m;
    return write_surface_mesh(path, points);
  }
  write_xyz_file(path.string(), stage.observed.cloud_m);
}

}  // namespace

void write_trial(const Trial& trial, const std::string& directory) {
  const fs::path dir(directory);
  // Built first: an inconsistent trial throws before anything is written.
  const ordered_json manifest = trial_json(trial, dir);
  create_directories_durably(dir);
  for (const TrialStage& stage : trial.stages) write_observation(stage, dir);
  // The manifest last, so a trial.json never names files that were not written.
  write_file_atomically(dir / "trial.json", [&](std::ostream& out) { out << manifest.dump(2) << "\n"; });
}

}  // namespace twin
