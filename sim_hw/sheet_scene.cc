#include "sim_hw/sheet_scene.h"

#include <stdexcept>

namespace sim_hw {

SceneMesh sheet_scene_mesh(const twin::SheetMesh& sheet, const twin::VecX& x, const Albedo& albedo,
                           std::string name) {
  SceneMesh mesh;
  mesh.name = std::move(name);
  mesh.albedo = albedo;
  mesh.triangles = sheet.triangles;
  mesh.vertices.resize(sheet.vertex_count());
  update_sheet_vertices(mesh, x);
  return mesh;
}

void update_sheet_vertices(SceneMesh& mesh, const twin::VecX& x) {
  if (x.size() != 3 * static_cast<Eigen::Index>(mesh.vertices.size())) {
    throw std::invalid_argument("sheet positions: " + std::to_string(x.size()) + " values for " +
                                std::to_string(mesh.vertices.size()) + " vertices (expected 3 per vertex)");
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) mesh.vertices[i] = x.segment<3>(3 * i);
}

}  // namespace sim_hw
