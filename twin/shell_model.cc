#include "twin/shell_model.h"

#include <numeric>

namespace twin {
namespace {

const SheetMesh& validated(const SheetMesh& mesh) {
  validate_sheet_mesh(mesh);
  return mesh;
}

const Material& validated(const Material& material) {
  material.validate();
  return material;
}

}  // namespace

std::vector<double> lumped_vertex_masses(const SheetMesh& mesh, double surface_density_kg_m2) {
  std::vector<double> masses(mesh.vertex_count(), 0.0);
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const double share = surface_density_kg_m2 * mesh.rest_area(t) / 3.0;
    for (int v : mesh.triangles[t]) masses[v] += share;
  }
  return masses;
}

ShellModel::ShellModel(SheetMesh mesh, const Material& material, const Vec3& gravity_m_s2)
    : mesh_(validated(mesh)),
      material_(validated(material)),
      masses_(lumped_vertex_masses(mesh_, material.surface_density_kg_m2)),
      membrane_(mesh_, material.membrane_stiffness()),
      bending_(mesh_, material.bending_rigidity_u_Nm, material.bending_rigidity_v_Nm),
      gravity_(masses_, gravity_m_s2) {
  apply_bending_effects(material_.effects);
}

void ShellModel::apply_bending_effects(const ModelEffects& effects) {
  bending_.set_rest_curvature(
      {effects.rest_curvature_uu_1_m, effects.rest_curvature_vv_1_m, effects.rest_curvature_uv_1_m});
  bending_.set_stiffening(effects.bending_stiffening_m2);
}

void ShellModel::set_material(const Material& material) {
  material.validate();
  // Bending first: it is the only update that can reject the material, and nothing else has
  // changed yet if it does.
  bending_.set_rigidity(material.bending_rigidity_u_Nm, material.bending_rigidity_v_Nm);
  apply_bending_effects(material.effects);  // cannot throw for a validated material
  material_ = material;
  masses_ = lumped_vertex_masses(mesh_, material.surface_density_kg_m2);
  membrane_.set_stiffness(material.membrane_stiffness());
  gravity_.set_masses(masses_);
}

double ShellModel::total_mass_kg() const {
  return std::accumulate(masses_.begin(), masses_.end(), 0.0);
}

}  // namespace twin
