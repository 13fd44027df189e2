#pragma once
// The sheet as a mechanical system: rest mesh, material, lumped masses and the energy terms of
// its potential energy (membrane + hinge bending + gravity). Solvers add inertia and viscosity
// for dynamics. Changing the material (as identification does thousands of times) updates the
// terms in place; topology, calibration and colourings are built once. Of the optional effects
// (model_effects.h) the rest curvature and the bending stiffening act through the bending term.

#include <memory>

#include "twin/bending_term.h"
#include "twin/gravity_term.h"
#include "twin/material.h"
#include "twin/membrane_term.h"
#include "twin/sheet_mesh.h"

namespace twin {

class ShellModel {
 public:
  // Throws std::invalid_argument for an invalid mesh or material (naming the field).
  ShellModel(SheetMesh mesh, const Material& material,
             const Vec3& gravity_m_s2 = Vec3(0.0, 0.0, -kStandardGravity));
  ShellModel(const ShellModel&) = delete;
  ShellModel& operator=(const ShellModel&) = delete;

  void set_material(const Material& material);

  const SheetMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  int vertex_count() const { return mesh_.vertex_count(); }
  const std::vector<double>& vertex_masses_kg() const { return masses_; }
  double total_mass_kg() const;

  const MembraneTerm& membrane() const { return membrane_; }
  const BendingTerm& bending() const { return bending_; }
  BendingTerm& bending() { return bending_; }
  const GravityTerm& gravity() const { return gravity_; }
  // The potential-energy terms, in a fixed order.
  std::vector<const EnergyTerm*> potential_terms() const { return {&membrane_, &bending_, &gravity_}; }

 private:
  void apply_bending_effects(const ModelEffects& effects);

  SheetMesh mesh_;
  Material material_;
  std::vector<double> masses_;
  MembraneTerm membrane_;
  BendingTerm bending_;
  GravityTerm gravity_;
};

// Lumped masses (kg): a third of each triangle's mass to each of its vertices.
std::vector<double> lumped_vertex_masses(const SheetMesh& mesh, double surface_density_kg_m2);

}  // namespace twin
