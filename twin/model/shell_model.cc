#include "twin/model/shell_model.h"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

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
      load_age_s_(std::numeric_limits<double>::quiet_NaN()),
      masses_(lumped_vertex_masses(mesh_, material.surface_density_kg_m2)),
      membrane_(mesh_, material.membrane_stiffness()),
      quadratic_membrane_(mesh_.quadratic_patches.empty()
                              ? nullptr
                              : std::make_unique<QuadraticMembraneTerm>(mesh_, material.membrane_stiffness())),
      // With the plate model the hinge term is not part of the energy: any valid rigidity will do.
      bending_(mesh_, material.bending_model == Material::BendingModel::kPlate ? 1e-3 : material.bending_rigidity_u_Nm,
               material.bending_model == Material::BendingModel::kPlate ? 1e-3 : material.bending_rigidity_v_Nm),
      plate_(material.bending_model == Material::BendingModel::kPlate
                 ? std::make_unique<PlateBendingTerm>(mesh_, material.plate_rigidity())
                 : nullptr),
      gravity_(masses_, gravity_m_s2),
      grip_(mesh_.vertex_count()),
      slip_(mesh_.vertex_count()) {
  grip_.set_grip(material_.effects.clamp_grip_strength, material_.effects.clamp_grip_width_m);
  slip_.set_compliance(material_.effects.clamp_slip_compliance_m_N);
  apply_bending_effects(material_.effects);
  // A relaxing material starts fully relaxed (the age is unknown until someone sets it).
  if (stiffness_factor() != 1.0) update_stiffness(material_, load_age_s_);
}

void ShellModel::apply_bending_effects(const ModelEffects& effects) {
  bending_.set_rest_curvature(
      {effects.rest_curvature_uu_1_m, effects.rest_curvature_vv_1_m, effects.rest_curvature_uv_1_m});
  bending_.set_stiffening(effects.bending_stiffening_m2);
  if (plate_) {
    plate_->set_rest_curvature(
        {effects.rest_curvature_uu_1_m, effects.rest_curvature_vv_1_m, effects.rest_curvature_uv_1_m});
    plate_->set_stiffening(effects.bending_stiffening_m2);
  }
}

void ShellModel::update_stiffness(const Material& material, double age_s) {
  const double factor = material.effects.relaxation_factor(age_s);
  // Bending first: it is the only update that can reject the material, and nothing else has
  // changed yet if it does.
  if (plate_) {
    plate_->set_rigidity(factor * material.plate_rigidity());
  } else {
    bending_.set_rigidity(factor * material.bending_rigidity_u_Nm, factor * material.bending_rigidity_v_Nm);
  }
  membrane_.set_stiffness(factor * material.membrane_stiffness());
  if (quadratic_membrane_) quadratic_membrane_->set_stiffness(factor * material.membrane_stiffness());
}

void ShellModel::update_masses() {
  masses_ = lumped_vertex_masses(mesh_, material_.surface_density_kg_m2);
  const double marker_kg = material_.effects.marker_mass_kg;
  if (marker_kg != 0.0) {
    for (const MaterialPointLocation& m : markers_) {
      for (int k = 0; k < 3; ++k) masses_[m.vertices[k]] += marker_kg * m.weights(k);
    }
  }
  gravity_.set_masses(masses_);
}

void ShellModel::set_material(const Material& material) {
  material.validate();
  if (material.bending_model != material_.bending_model) {
    throw std::invalid_argument("material '" + material.name + "': bending model '" +
                                (material.bending_model == Material::BendingModel::kPlate ? "plate" : "hinge") +
                                "' differs from the one this sheet model was built with");
  }
  update_stiffness(material, load_age_s_);
  apply_bending_effects(material.effects);  // cannot throw for a validated material
  material_ = material;
  grip_.set_grip(material.effects.clamp_grip_strength, material.effects.clamp_grip_width_m);
  slip_.set_compliance(material.effects.clamp_slip_compliance_m_N);
  update_masses();
}

void ShellModel::set_clamp_grips(const ClampSet& clamps) { grip_.set_clamps(mesh_, clamps); }

void ShellModel::set_clamp_slips(const ClampSet& clamps) { slip_.set_clamps(mesh_, clamps); }

void ShellModel::set_clamps_of_material_effects(const ClampSet& clamps) {
  if (material_.effects.clamp_grip_strength > 0.0) set_clamp_grips(clamps);
  if (material_.effects.clamp_slip_compliance_m_N > 0.0) set_clamp_slips(clamps);
}

DofMap ShellModel::hold_clamps(const ClampSet& clamps, const std::vector<ClampPose>& poses) const {
  grip_.set_engaged(poses);
  slip_.set_poses(poses);
  if (slip_.has_clamps()) return DofMap(std::vector<char>(vertex_count(), 0));
  return DofMap(clamps.fixed_vertices(vertex_count(), poses));
}

void ShellModel::set_marker_points(std::vector<MaterialPointLocation> markers) {
  for (std::size_t i = 0; i < markers.size(); ++i) {
    for (int v : markers[i].vertices) {
      if (v < 0 || v >= vertex_count()) {
        throw std::invalid_argument("ShellModel::set_marker_points: marker " + std::to_string(i) +
                                    " names vertex " + std::to_string(v) + ", expected 0.." +
                                    std::to_string(vertex_count() - 1));
      }
    }
  }
  markers_ = std::move(markers);
  update_masses();
}

void ShellModel::set_marker_points(const MaterialPointMap& markers) {
  std::vector<MaterialPointLocation> locations;
  for (int i = 0; i < markers.size(); ++i) locations.push_back(markers.location(i));
  set_marker_points(std::move(locations));
}

void ShellModel::set_load_age_s(double age_s) {
  if (age_s < 0.0) {
    throw std::invalid_argument("ShellModel::set_load_age_s: the age must be >= 0 s or NaN "
                                "(unknown), got " + std::to_string(age_s));
  }
  // Same factor, nothing to update (always so without relaxation): most stages cost nothing.
  if (material_.effects.relaxation_factor(age_s) != stiffness_factor()) update_stiffness(material_, age_s);
  load_age_s_ = age_s;
}

double ShellModel::total_mass_kg() const {
  return std::accumulate(masses_.begin(), masses_.end(), 0.0);
}

}  // namespace twin
