#pragma once
// What a simulated camera sees: triangle meshes in the cell frame (m, z up) with a colour each,
// and optionally an infinite horizontal floor. The cell's fake-hardware world builds one snapshot
// per frame (the true sheet from the twin, the table, the floor).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace sim_hw {

// RGB albedo, 0..255 per channel (what the surface looks like under full light).
using Albedo = Eigen::Vector3f;

struct SceneMesh {
  std::string name;
  std::vector<Eigen::Vector3d> vertices;  // cell frame, m
  std::vector<std::array<int, 3>> triangles;
  Albedo albedo{40.0f, 40.0f, 45.0f};  // dark prepreg by default
};

// The plane z = height_m of the cell frame, seen from both sides.
struct FloorPlane {
  double height_m = 0.0;
  Albedo albedo{170.0f, 170.0f, 165.0f};
};

struct RenderScene {
  std::vector<SceneMesh> meshes;
  std::optional<FloorPlane> floor;
  // Direction towards the (distant) light in the cell frame; Lambert shading for colour.
  Eigen::Vector3d light_direction_cell{0.3, 0.2, 1.0};
  Albedo background{90.0f, 90.0f, 95.0f};  // colour where a ray hits nothing
};

// A snapshot of the scene at a simulation time (s since the camera was activated).
using SceneSource = std::function<std::shared_ptr<const RenderScene>(double sim_time_s)>;

// An axis-aligned box (12 triangles, outward), e.g. a table top, in the cell frame (m).
SceneMesh make_box_mesh(std::string name, const Eigen::Vector3d& min_corner,
                        const Eigen::Vector3d& max_corner, const Albedo& albedo);

// A flat rectangle of (nx x ny) cells, 2 triangles each, centred at `centre` and spanned by the
// unit vectors u, v (m): a test target and the benchmark's stand-in sheet.
SceneMesh make_grid_mesh(std::string name, const Eigen::Vector3d& centre, const Eigen::Vector3d& u,
                         const Eigen::Vector3d& v, double size_u_m, double size_v_m, int nx, int ny,
                         const Albedo& albedo);

}  // namespace sim_hw
