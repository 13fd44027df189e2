#include "twin/model/membrane_term.h"

namespace twin {

MembraneTerm::MembraneTerm(const SheetMesh& mesh, const Mat3& stiffness_N_m)
    : stiffness_(stiffness_N_m) {
  std::vector<int> vertices;
  vertices.reserve(3 * mesh.triangle_count());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    elements_.push_back(make_membrane_element(mesh, t));
    vertices.insert(vertices.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
  }
  set_elements(std::move(vertices), mesh.vertex_count());
}

}  // namespace twin
