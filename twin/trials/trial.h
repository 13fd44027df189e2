#pragma once
// A scanned trial (issue 3): a sheet held by clamps through stages, observed at each stage as
// marker positions (or an unordered point cloud). The format is a directory, documented in
// docs/file_formats.md ("Trial directory"); in short:
//
//   trial.json
//   {
//     "material": "composite",
//     "sheet": {"width_m": 1.17, "height_m": 0.975}        (a rectangle; u across, v up)
//           or {"mesh_file": "specimen.obj"},               (any flat mesh, x, y = u, v in m)
//     "thickness_m": 0.0003,
//     "mass_kg": 0.342,  and/or  "surface_density_kg_m2": 0.3,
//     "markers": {"grid": {"rows": 17, "cols": 17, "spacing_m": [0.07, 0.058],
//                          "origin_m": [0.025, 0.02]}}
//             or {"list_m": [[u, v], ...]},
//     "clamps": [{"id": "A", "material_point_m": [u, v], "grip_radius_m": 0.02}, ...],
//     "stages": [
//       {"id": "1", "time_s": 0.0,                           (time optional)
//        "clamps_moved_at_s": 0.0,                            (optional, see stage_age.h)
//        "clamps": {"A": [x, y, z], "B": [x, y, z], "C": "released", ...},
//        "markers_file": "1.xyz",                             (one x y z line per marker)
//        "scan_file": "1_scan.xyz"},                          (optional raw scanner points)
//       {"id": "5", "clamps": {...}, "cloud_file": "5_cloud.xyz"}   (unordered points, or .ply/.obj)
//     ]
//   }
//
// Grid markers are numbered row-major: marker r * cols + c sits at origin + (c du, r dv).
// Positions are metres in the world frame, z up (gravity along -z). A marker that was not seen
// (under a clamp, say) is "nan nan nan" in its stage's file. Every stage must say where every
// clamp is or that it is released; stages are in the order the clamps really moved.

#include <optional>
#include <string>
#include <vector>

#include "twin/model/clamp.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

// What was seen of the sheet at one stage.
struct StageObservation {
  // Per marker, in manifest order (m, world); NaN components for a marker not seen. Empty when
  // the stage was observed as a cloud instead.
  std::vector<Vec3> markers_m;
  // Unordered points on the sheet (m, world), for stages without marker correspondence.
  std::vector<Vec3> cloud_m;
  bool has_markers() const { return !markers_m.empty(); }
  int seen_marker_count() const;
};

struct TrialStage {
  std::string id;
  std::optional<double> time_s;             // when the stage was scanned (s)
  // When the clamps reached this stage's poses (s, <= time_s, >= the previous stage's time_s);
  // absent: see stage_load_ages_s (stage_age.h) for the default.
  std::optional<double> clamps_moved_at_s;
  // Per clamp, in Trial::clamps order: its pose at this stage (orientation identity: the
  // clamps' jaws stay level); engaged = false for a released clamp.
  std::vector<ClampPose> poses;
  StageObservation observed;
  std::string markers_file, cloud_file, scan_file;  // as named in trial.json ("" if absent)
};

struct TrialSheet {
  // Exactly one of: a rectangle (width_m, height_m > 0), or a mesh file.
  double width_m = 0.0, height_m = 0.0;
  std::string mesh_file;  // absolute path once read
  bool is_rectangle() const { return mesh_file.empty(); }
};

struct Trial {
  std::string directory;                 // where trial.json was read from
  std::string material_name;
  TrialSheet sheet;
  double thickness_m = 0.0;
  std::optional<double> mass_kg;
  std::optional<double> surface_density_kg_m2;
  std::vector<Vec2> marker_uv_m;         // material coordinates of the markers
  std::optional<int> marker_grid_rows, marker_grid_cols;  // set when given as a grid
  std::vector<ClampSpec> clamps;
  std::vector<TrialStage> stages;

  // Surface density (kg/m^2): the given one, else mass / sheet area.
  double density_kg_m2(double sheet_area_m2) const;
};

// Reads and checks a trial directory. Throws std::invalid_argument / std::runtime_error whose
// message names the file, and the field or line, and what was expected: missing files,
// non-numeric or non-finite values, marker counts that differ from the manifest, unknown clamp
// ids, clamps farther apart in the world than on the sheet, density that disagrees with
// mass / area by more than 5 %, markers or clamps off the sheet.
Trial read_trial(const std::string& directory);

// The farthest apart (m) two engaged clamps may be in a stage of a trial file when their
// material points are `sheet_distance_m` apart on the sheet: a sheet barely stretches, so 2 %
// more, plus 5 mm for clamp placement and measurement error. read_trial rejects stages beyond.
double max_clamp_distance_m(double sheet_distance_m);

// The trial's rest mesh: the rectangle meshed with about `target_triangles` triangles
// (make_rectangular_sheet), or the given mesh file as it is.
SheetMesh trial_sheet_mesh(const Trial& trial, int target_triangles);

// How the twin of a trial's sheet is meshed: about `triangles` triangles (ignored for a sheet
// given as a mesh file), then refined once per radius near every clamp's material point
// (mesh_refinement.h; each level halves the edges within that distance, in m). Where a clamp
// holds the sheet it is sharply curved, and a coarse triangle would hold more than the jaws do.
//
// path_triangles: the mesh on which a fresh simulation follows the clamps' path from the flat
// sheet (trial_evaluator.h), when every stage is scanned with markers and that mesh is well
// under the twin's (below 2/3 of its triangles); 0 follows it on the twin itself.
//
// resolve_jaws: instead of given radii, refine near each clamp until its jaws are resolved
// (jaw_refinement_radii_m); clamp_refinement_radii_m must then be empty.
//
// quadratic_membrane: the mesh above is made with a quarter of the triangles (a sheet given as a
// mesh file: as given), refined near the clamps so that the final edges resolve the jaws, then
// refined uniformly once (refine_uniformly): the twin has about `triangles` triangles, and its
// membrane is quadratic on the coarser ones (shell_model.h). The path mesh stays linear.
struct TwinMeshSpec {
  int triangles = 1500;
  std::vector<double> clamp_refinement_radii_m;
  int path_triangles = 300;
  bool resolve_jaws = false;
  bool quadratic_membrane = false;
};
SheetMesh trial_sheet_mesh(const Trial& trial, const TwinMeshSpec& spec);

// `mesh` refined once per radius (m) near every clamp's material point (mesh_refinement.h).
SheetMesh refine_near_clamps(const SheetMesh& mesh, const std::vector<ClampSpec>& clamps,
                             const std::vector<double>& radii_m);

// The refinement levels (radii in m, outermost first) that resolve a clamp's jaws on `mesh`:
// enough levels that the edges within the grip radius r are at most 0.4 r (some 20-30 vertices
// held, so the jaws act as a gripped disk of radius r whatever the mesh; a coarser grip holds
// one triangle, larger or smaller than the jaws, and the hanging shape near the clamp, which
// decides much of the sheet's, changes with the mesh). The last level reaches r, each coarser
// one twice as far (r 2^k): on the lab's 1500-triangle composite twin (4 cm edges, 1.5 cm
// jaws) 0.06, 0.03, 0.015 m, 2508 triangles. (Spacing the radii by two coarse edges instead,
// as mesh_refinement.h suggests, gave 6 % more triangles and the same smallest angle, 13.9
// degrees.) None for a pin (r = 0) or where the mesh's edges (mean of the host triangle's)
// are already fine enough.
// Throws std::invalid_argument when the clamp's material point is off the sheet.
// uniform_refinements_after: how many times the result will be refined uniformly after (each
// halves the edges), counted in the edges the jaws must be resolved by.
std::vector<double> jaw_refinement_radii_m(const SheetMesh& mesh, const ClampSpec& clamp,
                                           int uniform_refinements_after = 0);

// `mesh` refined near every clamp by its own jaw_refinement_radii_m.
SheetMesh refine_to_resolve_jaws(const SheetMesh& mesh, const std::vector<ClampSpec>& clamps,
                                 int uniform_refinements_after = 0);

// Writes trial.json and every stage's marker / cloud files into `directory` (created if
// needed; files replaced atomically). File names are the stages' markers_file / cloud_file,
// or "<id>.xyz" / "<id>_cloud.xyz" when empty. Raw scans are written by whoever made them.
void write_trial(const Trial& trial, const std::string& directory);

// Plain-text point files: one "x y z" line per point; "nan nan nan" allowed when allow_nan.
// Blank lines and lines starting with '#' are skipped. Errors name file:line.
std::vector<Vec3> read_xyz_file(const std::string& path, bool allow_nan);
void write_xyz_file(const std::string& path, const std::vector<Vec3>& points);

}  // namespace twin
