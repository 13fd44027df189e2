#pragma once
// The scene of issue 4's end-to-end checks: the paper's composite sheet hanging from four clamps
// (the twin's equilibrium, the "truth"), a prediction of it made with a different material (what
// an imperfect twin would predict), and three D415s 1.2-1.8 m from the sheet, as in the paper's
// cell (front, left and right, looking down at it).

#include <vector>

#include <Eigen/Geometry>

#include "drivers/depth_camera.h"
#include "tracking/surface_mesh.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace integration {

struct HangingSheet {
  twin::SheetMesh mesh;
  twin::VecX truth_m;       // true equilibrium (m, cell frame)
  twin::VecX prediction_m;  // the equilibrium with bending x4 and tensile / 2
};

// Meshes of about `triangles` triangles; throws std::runtime_error if a solve fails.
HangingSheet make_hanging_sheet(int triangles);

// The twin's mesh at positions x as the tracker's plain mesh.
tracking::SurfaceMesh to_surface_mesh(const twin::SheetMesh& mesh, const twin::VecX& x);

// Camera frame (x right, y down, z forward) at `eye` looking at `target`, cell z up.
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// Three simulated D415 configs around the sheet, each 1.2-1.8 m from its centre.
std::vector<drivers::CameraConfig> three_cameras(const twin::VecX& sheet_m, int width = 848,
                                                 int height = 480);

// Distance (m) from each point to the nearest point of the triangle mesh (exact, brute force
// with a bounding-sphere cut).
std::vector<double> distances_to_surface(const std::vector<Eigen::Vector3d>& points,
                                         const twin::SheetMesh& mesh, const twin::VecX& x);

}  // namespace integration
