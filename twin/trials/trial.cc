#include "twin/trials/trial.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "twin/base/atomic_file.h"
#include "twin/model/clamp_json.h"
#include "twin/base/json_field.h"
#include "twin/mesh/mesh_io.h"
#include "twin/mesh/mesh_io_internal.h"
#include "twin/mesh/material_point.h"
#include "twin/mesh/mesh_refinement.h"
#include "twin/trials/stage_age.h"
#include "twin/trials/trial_internal.h"

namespace twin {
namespace {

namespace fs = std::filesystem;
using trial_internal::describe_uv;
using trial_internal::resolve;
using ordered_json = nlohmann::ordered_json;

// A marker or clamp point this close to the sheet counts as on it: printed coordinates lose
// nothing at max_digits10, but hand-written ones on the very edge may round outwards.
constexpr double kOnSheetTolerance_m = 1e-6;
// Mass and surface density must tell the same story within this fraction of mass / area.
constexpr double kDensityTolerance = 0.05;
// See max_clamp_distance_m.
constexpr double kClampStretchFraction = 0.02;
constexpr double kClampStretchAllowance_m = 0.005;
// Bounds a grid before allocating it (a 1000 x 1000 grid is far beyond any scanned sheet).
constexpr long long kMaxMarkers = 1000000;

// Stage ids become default file names ("<id>.xyz"): plain, unique file-name words only.
bool is_plain_file_word(const std::string& id) {
  static const std::string allowed =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-";
  return !id.empty() && id != "." && id != ".." && id.find_first_not_of(allowed) == std::string::npos;
}

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double distance_to_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Distance from p to the counter-clockwise triangle abc (0 inside).
double distance_to_triangle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& p) {
  if (cross(b - a, p - a) >= 0.0 && cross(c - b, p - b) >= 0.0 && cross(a - c, p - c) >= 0.0) {
    return 0.0;
  }
  return std::min({distance_to_segment(a, b, p), distance_to_segment(b, c, p),
                   distance_to_segment(c, a, p)});
}

// The part of the material plane the sheet covers: its rectangle, or the union of the rest
// triangles of its mesh (which may have holes or a curved outline).
class SheetRegion {
 public:
  explicit SheetRegion(const TrialSheet& sheet) : sheet_(sheet) {
    if (!sheet.is_rectangle()) mesh_ = read_flat_sheet_mesh(sheet.mesh_file);
  }

  bool contains(const Vec2& uv_m) const {
    if (!uv_m.allFinite()) return false;
    if (sheet_.is_rectangle()) {
      const double t = kOnSheetTolerance_m;
      return uv_m.x() >= -t && uv_m.x() <= sheet_.width_m + t && uv_m.y() >= -t &&
             uv_m.y() <= sheet_.height_m + t;
    }
    for (const auto& tri : mesh_.triangles) {
      const double d = distance_to_triangle(mesh_.rest_uv[tri[0]], mesh_.rest_uv[tri[1]],
                                            mesh_.rest_uv[tri[2]], uv_m);
      if (d <= kOnSheetTolerance_m) return true;
    }
    return false;
  }

  double area_m2() const {
    return sheet_.is_rectangle() ? sheet_.width_m * sheet_.height_m : mesh_.total_rest_area();
  }

  std::string describe() const {
    if (sheet_.is_rectangle()) {
      return fmt::format("the {:.6g} x {:.6g} m rectangle", sheet_.width_m, sheet_.height_m);
    }
    return "the rest triangles of " + sheet_.mesh_file;
  }

 private:
  TrialSheet sheet_;
  SheetMesh mesh_;
};

// ---------------------------------------------------------------- reading trial.json

TrialSheet read_sheet(const JsonField& f, const fs::path& directory) {
  f.only_keys({"width_m", "height_m", "mesh_file"});
  TrialSheet sheet;
  if (auto file = f.optional("mesh_file")) {
    for (const char* k : {"width_m", "height_m"}) {
      if (f.has(k)) f[k].fail("cannot be combined with mesh_file");
    }
    const fs::path path = resolve(directory, file->string());
    if (!fs::is_regular_file(path)) file->fail("names a file that does not exist: " + path.string());
    sheet.mesh_file = fs::absolute(path).lexically_normal().string();
    return sheet;
  }
  sheet.width_m = f["width_m"].positive("m");
  sheet.height_m = f["height_m"].positive("m");
  return sheet;
}

// The sheet's region, with errors from the mesh file reported against the field naming it.
SheetRegion sheet_region(const JsonField& sheet_field, const TrialSheet& sheet) {
  try {
    return SheetRegion(sheet);
  } catch (const std::exception& e) {
    sheet_field["mesh_file"].fail(std::string("cannot be used as the sheet: ") + e.what());
  }
}

void read_markers(const JsonField& f, Trial& t) {
  f.only_keys({"grid", "list_m"});
  if (f.has("grid") == f.has("list_m")) {
    f.fail_child("grid", "or 'list_m' must be given, exactly one of them");
  }
  if (auto list = f.optional("list_m")) {
    const std::size_t n = list->array_size();
    if (n == 0) list->fail("must list at least one marker [u, v] (m)");
    for (std::size_t i = 0; i < n; ++i) t.marker_uv_m.push_back((*list)[i].vec2("m"));
    return;
  }
  const JsonField g = f["grid"];
  g.only_keys({"rows", "cols", "spacing_m", "origin_m"});
  const int rows = g["rows"].positive_integer();
  const int cols = g["cols"].positive_integer();
  if (static_cast<long long>(rows) * cols > kMaxMarkers) {
    g.fail(fmt::format("has {} x {} markers, more than the {} a trial may have", rows, cols, kMaxMarkers));
  }
  const JsonField spacing_field = g["spacing_m"];
  const Vec2 spacing_m = spacing_field.vec2("m");
  if (!(spacing_m.x() > 0.0 && spacing_m.y() > 0.0)) {
    spacing_field.fail("must be two positive spacings [du, dv] in m, got " + describe_uv(spacing_m));
  }
  const Vec2 origin_m = g["origin_m"].vec2("m");
  // Row-major: marker r * cols + c.
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      t.marker_uv_m.push_back(origin_m + Vec2(c * spacing_m.x(), r * spacing_m.y()));
    }
  }
  t.marker_grid_rows = rows;
  t.marker_grid_cols = cols;
}

void check_markers_on_sheet(const JsonField& markers, const Trial& t, const SheetRegion& region) {
  for (std::size_t i = 0; i < t.marker_uv_m.size(); ++i) {
    if (!region.contains(t.marker_uv_m[i])) {
      const std::string where = t.marker_grid_rows ? "grid" : "list_m[" + std::to_string(i) + "]";
      markers.fail_child(where, fmt::format("puts marker {} at {}, which is not on the sheet ({})", i,
                                            describe_uv(t.marker_uv_m[i]), region.describe()));
    }
  }
}

void read_clamps(const JsonField& f, const SheetRegion& region, Trial& t) {
  if (f.array_size() == 0) f.fail("must list at least one clamp");
  for (std::size_t i = 0; i < f.array_size(); ++i) {
    const JsonField c = f[i];
    const ClampSpec spec = read_clamp_spec(c);
    for (const ClampSpec& earlier : t.clamps) {
      if (earlier.id == spec.id) c["id"].fail("\"" + spec.id + "\" is used by an earlier clamp");
    }
    if (!region.contains(spec.material_point_m)) {
      c["material_point_m"].fail(describe_uv(spec.material_point_m) + " is not on the sheet (" +
                                 region.describe() + ")");
    }
    t.clamps.push_back(spec);
  }
}

// Every clamp must be named: where it is, or "released". Orientation stays identity.
std::vector<ClampPose> read_poses(const JsonField& f, const Trial& t) {
  if (!f.is_object()) f.fail("must be an object {\"clamp id\": [x, y, z] or \"released\", ...}");
  for (const auto& item : f.json().items()) {
    const bool known = std::any_of(t.clamps.begin(), t.clamps.end(),
                                   [&](const ClampSpec& c) { return c.id == item.key(); });
    if (!known) f[item.key()].fail("names no clamp of the 'clamps' list");
  }
  std::vector<ClampPose> poses;
  for (const ClampSpec& clamp : t.clamps) {
    if (!f.has(clamp.id)) {
      f.fail_child(clamp.id, "is missing: every stage says where every clamp is, or \"released\"");
    }
    const JsonField p = f[clamp.id];
    ClampPose pose;
    if (p.is_string()) {
      if (p.string() != "released") p.fail("must be [x, y, z] (m) or \"released\"");
      pose.engaged = false;
    } else {
      pose.position_m = p.vec3("m");
    }
    poses.push_back(pose);
  }
  if (std::none_of(poses.begin(), poses.end(), [](const ClampPose& p) { return p.engaged; })) {
    f.fail("leave no clamp holding the sheet: every stage needs at least one");
  }
  return poses;
}

// Clamps hold a sheet that barely stretches, so two engaged clamps cannot be much farther
// apart in the world than their material points are on the sheet; if they are, a position or
// a material point is wrong (a swapped id, a unit slip).
void check_clamp_distances(const JsonField& f, const Trial& t, const TrialStage& stage) {
  for (std::size_t i = 0; i < t.clamps.size(); ++i) {
    for (std::size_t j = i + 1; j < t.clamps.size(); ++j) {
      if (!stage.poses[i].engaged || !stage.poses[j].engaged) continue;
      const double world_m = (stage.poses[i].position_m - stage.poses[j].position_m).norm();
      const double sheet_m = (t.clamps[i].material_point_m - t.clamps[j].material_point_m).norm();
      if (world_m > max_clamp_distance_m(sheet_m)) {
        f.fail(fmt::format(
            "(stage '{}') put clamps '{}' and '{}' {:.4f} m apart in the world, but they are "
            "{:.4f} m apart on the sheet (at most {:g} % + {:g} mm more is possible)",
            stage.id, t.clamps[i].id, t.clamps[j].id, world_m, sheet_m,
            100.0 * kClampStretchFraction, 1000.0 * kClampStretchAllowance_m));
      }
    }
  }
}

// The path of a stage file named by field f, which must exist.
fs::path existing_file(const JsonField& f, const fs::path& directory) {
  const std::string name = f.string();
  if (name.empty()) f.fail("must not be empty");
  const fs::path path = resolve(directory, name);
  if (!fs::is_regular_file(path)) f.fail("names a file that does not exist: " + path.string());
  return path;
}

std::vector<Vec3> read_stage_markers(const JsonField& f, const fs::path& directory,
                                     const Trial& t) {
  const fs::path path = existing_file(f, directory);
  if (t.marker_uv_m.empty()) f.fail("needs the markers to be listed in the field 'markers'");
  std::vector<Vec3> markers = read_xyz_file(path.string(), true);
  if (markers.size() != t.marker_uv_m.size()) {
    f.fail(fmt::format("names {}, which has {} marker lines; expected {}, one per marker of the "
                       "field 'markers'",
                       path.string(), markers.size(), t.marker_uv_m.size()));
  }
  return markers;
}

std::vector<Vec3> read_stage_cloud(const JsonField& f, const fs::path& directory) {
  const fs::path path = existing_file(f, directory);
  const std::string ext = internal::lower_extension(path);
  std::vector<Vec3> cloud;
  if (ext == ".xyz") {
    cloud = read_xyz_file(path.string(), false);
  } else if (ext == ".ply" || ext == ".obj") {
    cloud = read_surface_mesh(path).positions;
  } else {
    f.fail("must name a .xyz, .ply or .obj file, got " + path.string());
  }
  if (cloud.empty()) f.fail("names " + path.string() + ", which holds no points");
  return cloud;
}

TrialStage read_stage(const JsonField& st, const fs::path& directory, const Trial& t) {
  st.only_keys({"id", "time_s", "clamps_moved_at_s", "clamps", "markers_file", "cloud_file", "scan_file"});
  TrialStage stage;
  stage.id = st["id"].string();
  if (!is_plain_file_word(stage.id)) {
    st["id"].fail("must be letters, digits, '_', '.' or '-' (it names files), got \"" + stage.id + "\"");
  }
  for (const TrialStage& earlier : t.stages) {
    if (earlier.id == stage.id) st["id"].fail("\"" + stage.id + "\" is used by an earlier stage");
  }
  if (auto time = st.optional("time_s")) stage.time_s = time->number("s");
  if (auto moved = st.optional("clamps_moved_at_s")) {
    stage.clamps_moved_at_s = moved->number("s");
    if (!stage.time_s) moved->fail("needs the stage's 'time_s' (when it was scanned)");
    if (*stage.clamps_moved_at_s > *stage.time_s) {
      moved->fail(fmt::format("is {} s, later than the stage's time_s {} s: the clamps must have "
                              "reached their poses before the scan", *stage.clamps_moved_at_s, *stage.time_s));
    }
  }
  stage.poses = read_poses(st["clamps"], t);
  check_clamp_distances(st["clamps"], t, stage);
  if (st.has("markers_file") == st.has("cloud_file")) {
    st.fail_child("markers_file", "or 'cloud_file' must be given, exactly one of them");
  }
  if (auto m = st.optional("markers_file")) {
    stage.markers_file = m->string();
    stage.observed.markers_m = read_stage_markers(*m, directory, t);
  } else {
    stage.cloud_file = st["cloud_file"].string();
    stage.observed.cloud_m = read_stage_cloud(st["cloud_file"], directory);
  }
  if (auto scan = st.optional("scan_file")) {
    existing_file(*scan, directory);  // only its presence is checked: it is raw scanner data
    stage.scan_file = scan->string();
  }
  return stage;
}

void read_stages(const JsonField& f, const fs::path& directory, Trial& t) {
  if (f.array_size() == 0) f.fail("must list at least one stage");
  std::optional<double> last_time_s;
  for (std::size_t i = 0; i < f.array_size(); ++i) {
    TrialStage stage = read_stage(f[i], directory, t);
    if (stage.time_s) {
      if (last_time_s && *stage.time_s < *last_time_s) {
        f[i]["time_s"].fail(fmt::format("is {} s, earlier than the {} s of a stage before it: "
                                        "stages are in the order they happened",
                                        *stage.time_s, *last_time_s));
      }
    }
    // The clamps left the previous stage's poses after it was scanned; unless this stage scans the
    // same pose again (the same poses and the same moment the clamps stopped: a repeated scan).
    const bool repeated_scan = !t.stages.empty() && stage.clamps_moved_at_s && scans_same_pose(t.stages.back(), stage);
    if (stage.clamps_moved_at_s && last_time_s && *stage.clamps_moved_at_s < *last_time_s && !repeated_scan) {
      f[i]["clamps_moved_at_s"].fail(fmt::format("is {} s, earlier than the {} s at which the stage before it "
                                                 "was scanned", *stage.clamps_moved_at_s, *last_time_s));
    }
    if (stage.time_s) last_time_s = stage.time_s;
    t.stages.push_back(std::move(stage));
  }
}

// Mass and density given together must agree: a listed density is easily off by a factor of
// 100 (g vs kg, or another material's row), and the twin's weight would then be wrong.
void check_density(const JsonField& f, const Trial& t, double area_m2) {
  if (!t.mass_kg || !t.surface_density_kg_m2) return;
  const double implied_kg_m2 = *t.mass_kg / area_m2;
  if (std::abs(*t.surface_density_kg_m2 - implied_kg_m2) > kDensityTolerance * implied_kg_m2) {
    f["surface_density_kg_m2"].fail(fmt::format(
        "is {:.6g} kg/m^2, but mass_kg {:.6g} kg over the sheet's {:.6g} m^2 implies {:.3g} kg/m^2; "
        "they must agree within {:g} %",
        *t.surface_density_kg_m2, *t.mass_kg, area_m2, implied_kg_m2, 100.0 * kDensityTolerance));
  }
}
}  // namespace

int StageObservation::seen_marker_count() const {
  return static_cast<int>(
      std::count_if(markers_m.begin(), markers_m.end(), [](const Vec3& p) { return p.allFinite(); }));
}

double Trial::density_kg_m2(double sheet_area_m2) const {
  if (surface_density_kg_m2) return *surface_density_kg_m2;
  if (!mass_kg) throw std::invalid_argument("trial: neither mass_kg nor surface_density_kg_m2 is set");
  if (!(sheet_area_m2 > 0.0)) {
    throw std::invalid_argument(fmt::format("trial: sheet area must be positive, got {} m^2", sheet_area_m2));
  }
  return *mass_kg / sheet_area_m2;
}

double max_clamp_distance_m(double sheet_distance_m) {
  return sheet_distance_m * (1.0 + kClampStretchFraction) + kClampStretchAllowance_m;
}

Trial read_trial(const std::string& directory) {
  const fs::path dir(directory);
  const std::string manifest = (dir / "trial.json").string();
  const nlohmann::json j = JsonField::parse_file(manifest);
  const JsonField f(j, manifest);
  f.only_keys({"material", "sheet", "thickness_m", "mass_kg", "surface_density_kg_m2", "markers",
               "clamps", "stages"});
  Trial t;
  t.directory = directory;
  t.material_name = f["material"].string();
  if (t.material_name.empty()) f["material"].fail("must name the material");
  t.sheet = read_sheet(f["sheet"], dir);
  const SheetRegion region = sheet_region(f["sheet"], t.sheet);
  t.thickness_m = f["thickness_m"].positive("m");
  if (auto m = f.optional("mass_kg")) t.mass_kg = m->positive("kg");
  if (auto d = f.optional("surface_density_kg_m2")) t.surface_density_kg_m2 = d->positive("kg/m^2");
  if (!t.mass_kg && !t.surface_density_kg_m2) {
    f.fail_child("mass_kg", "or 'surface_density_kg_m2' must be given (or both)");
  }
  check_density(f, t, region.area_m2());
  if (auto markers = f.optional("markers")) {
    read_markers(*markers, t);
    check_markers_on_sheet(*markers, t, region);
  }
  read_clamps(f["clamps"], region, t);
  read_stages(f["stages"], dir, t);
  return t;
}

SheetMesh trial_sheet_mesh(const Trial& trial, int target_triangles) {
  if (!trial.sheet.is_rectangle()) return read_flat_sheet_mesh(trial.sheet.mesh_file);
  if (target_triangles < 1) {
    throw std::invalid_argument(fmt::format("trial_sheet_mesh: target_triangles must be >= 1, got {}",
                                            target_triangles));
  }
  const double w = trial.sheet.width_m, h = trial.sheet.height_m;
  return make_rectangular_sheet(w, h, edge_length_for_triangle_count(w, h, target_triangles));
}

SheetMesh refine_near_clamps(const SheetMesh& mesh, const std::vector<ClampSpec>& clamps,
                             const std::vector<double>& radii_m) {
  std::vector<Vec2> points;
  for (const ClampSpec& c : clamps) points.push_back(c.material_point_m);
  return refine_near_points(mesh, points, radii_m);
}

std::vector<double> jaw_refinement_radii_m(const SheetMesh& mesh, const ClampSpec& clamp,
                                           int uniform_refinements_after) {
  // Edges of at most 0.4 r: the disk then holds some 20-30 vertices.
  constexpr double kEdgesPerGripRadius = 2.5;
  constexpr int kMaxLevels = 8;  // a 256-fold finer edge: far beyond any real jaw
  if (!(std::isfinite(clamp.grip_radius_m) && clamp.grip_radius_m > 0.0)) return {};
  const auto host = locate_material_point(mesh, clamp.material_point_m);
  if (!host) {
    throw std::invalid_argument(fmt::format("clamp '{}': material point ({}, {}) m is not on the sheet", clamp.id,
                                            clamp.material_point_m.x(), clamp.material_point_m.y()));
  }
  double edge_m = 0.0;  // the host triangle's mean edge: the mesh's size at the clamp
  for (int k = 0; k < 3; ++k) {
    edge_m += (mesh.rest_uv[host->vertices[k]] - mesh.rest_uv[host->vertices[(k + 1) % 3]]).norm() / 3.0;
  }
  edge_m = std::ldexp(edge_m, -std::max(0, uniform_refinements_after));
  int levels = 0;
  for (double e = edge_m; e > clamp.grip_radius_m / kEdgesPerGripRadius && levels < kMaxLevels; e /= 2.0) ++levels;
  std::vector<double> radii_m(static_cast<std::size_t>(levels));
  for (int k = 0; k < levels; ++k) radii_m[static_cast<std::size_t>(k)] = std::ldexp(clamp.grip_radius_m, levels - 1 - k);
  return radii_m;
}

SheetMesh refine_to_resolve_jaws(const SheetMesh& mesh, const std::vector<ClampSpec>& clamps,
                                 int uniform_refinements_after) {
  std::vector<std::vector<double>> radii_m;
  std::size_t levels = 0;
  for (const ClampSpec& c : clamps) {
    radii_m.push_back(jaw_refinement_radii_m(mesh, c, uniform_refinements_after));
    levels = std::max(levels, radii_m.back().size());
  }
  // Level by level, each clamp's finest level last (clamps needing fewer levels start later).
  SheetMesh refined = mesh;
  for (std::size_t level = 0; level < levels; ++level) {
    for (std::size_t c = 0; c < clamps.size(); ++c) {
      const std::size_t first = levels - radii_m[c].size();
      if (level < first) continue;
      refined = refine_near_points(refined, {clamps[c].material_point_m}, {radii_m[c][level - first]});
    }
  }
  return refined;
}

SheetMesh trial_sheet_mesh(const Trial& trial, const TwinMeshSpec& spec) {
  const int uniform = spec.quadratic_membrane ? 1 : 0;
  const SheetMesh base = trial_sheet_mesh(trial, uniform ? std::max(2, spec.triangles / 4) : spec.triangles);
  SheetMesh refined;
  if (spec.resolve_jaws) {
    if (!spec.clamp_refinement_radii_m.empty()) {
      throw std::invalid_argument("twin mesh: give clamp refinement radii or resolve the jaws, not both");
    }
    refined = refine_to_resolve_jaws(base, trial.clamps, uniform);
  } else {
    refined = refine_near_clamps(base, trial.clamps, spec.clamp_refinement_radii_m);
  }
  return uniform ? refine_uniformly(refined) : refined;
}

}  // namespace twin
