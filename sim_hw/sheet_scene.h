#pragma once
// The twin's sheet as something a simulated camera can see: the sheet's triangles at given
// world positions (the twin's world frame is taken as the cell frame, m). The cell's fake world
// calls update_sheet_vertices once per frame and hands the scene out through a SceneSource.

#include <string>

#include "sim_hw/render_scene.h"
#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace sim_hw {

inline const Albedo kPrepregAlbedo{40.0f, 40.0f, 45.0f};

// Throws std::invalid_argument if x.size() != 3 * sheet.vertex_count().
SceneMesh sheet_scene_mesh(const twin::SheetMesh& sheet, const twin::VecX& x,
                           const Albedo& albedo = kPrepregAlbedo, std::string name = "sheet");

// Moves the mesh's vertices to x (same vertex count), without reallocating.
void update_sheet_vertices(SceneMesh& mesh, const twin::VecX& x);

}  // namespace sim_hw
