#pragma once
// The sheet as a mechanical system: rest mesh, material, lumped masses and the energy terms of
// its potential energy (membrane + hinge bending + gravity). Solvers add inertia and viscosity
// for dynamics. Changing the material (as identification does thousands of times) updates the
// terms in place; topology, calibration and colourings are built once. Of the optional effects
// (model_effects.h) the rest curvature and the bending stiffening act through the bending term.
//
// Two effects of the material (model_effects.h) need more than the material to apply:
//   - marker mass: where the scan markers are glued (set_marker_points). Each adds
//     effects.marker_mass_kg, shared among its host triangle's vertices by barycentric weight,
//     to the vertex masses that gravity and inertia use. Without markers (the cell's ply) the
//     effect has nothing to act on.
//   - viscoelastic relaxation: how long ago the clamps last moved (set_load_age_s). Tensile,
//     shear and bending stiffness are the material's times effects.relaxation_factor(age).
//     Whoever solves or differentiates a stage sets its age first (trial_simulation.h).
//   - clamp grip: which clamps hold the sheet (set_clamp_grips, before any solver is
//     built on the model) and which of them are engaged now (hold_clamps, which the
//     solvers call with the poses they are given). Without clamps set the effect has nothing
//     to act on.
//   - clamp slip: likewise (set_clamp_slips). With it the clamps' vertices are no longer held
//     fixed: springs (clamp_slip_term.h) hold them, so hold_clamps frees them.
//
// The membrane: linear triangles (membrane_term.h), or quadratic ones (quadratic_membrane.h)
// when the mesh was refined uniformly from a coarser one and so carries quadratic patches; the
// mesh decides (trial.h: TwinMeshSpec::quadratic_membrane). The strain-rate viscosity of
// dynamics stays on the linear triangles either way.

#include <memory>

#include "twin/model/bending_term.h"
#include "twin/model/clamp_grip_term.h"
#include "twin/model/clamp_slip_term.h"
#include "twin/model/dof_map.h"
#include "twin/model/gravity_term.h"
#include "twin/model/material.h"
#include "twin/mesh/material_point.h"
#include "twin/model/membrane_term.h"
#include "twin/model/plate_bending_term.h"
#include "twin/model/quadratic_membrane.h"
#include "twin/mesh/sheet_mesh.h"

namespace twin {

class ShellModel {
 public:
  // Throws std::invalid_argument for an invalid mesh or material (naming the field).
  ShellModel(SheetMesh mesh, const Material& material,
             const Vec3& gravity_m_s2 = Vec3(0.0, 0.0, -kStandardGravity));
  ShellModel(const ShellModel&) = delete;
  ShellModel& operator=(const ShellModel&) = delete;

  // The material's stiffnesses enter scaled by the relaxation factor at the current load age.
  // The bending model is the one the model was built with: a material of the other model
  // throws std::invalid_argument (solvers keep the terms they were built on).
  void set_material(const Material& material);

  // Scan markers on the sheet (locations in this model's mesh; throws std::invalid_argument for
  // a vertex id out of range). Replaces earlier ones; an empty list removes them.
  void set_marker_points(std::vector<MaterialPointLocation> markers);
  void set_marker_points(const MaterialPointMap& markers);
  const std::vector<MaterialPointLocation>& marker_points() const { return markers_; }

  // Seconds since the clamps last moved (NaN, the default: unknown, taken as fully relaxed).
  // Throws std::invalid_argument for a negative age.
  void set_load_age_s(double age_s);
  double load_age_s() const { return load_age_s_; }
  // The factor the stiffnesses carry now: material().effects.relaxation_factor(load_age_s()).
  double stiffness_factor() const { return material_.effects.relaxation_factor(load_age_s_); }

  // The clamps whose jaws the clamp-grip effect widens (clamp_grip_term.h). Call before solvers
  // are built on this model: they keep the sparsity pattern of its terms. The springs stay in
  // that pattern at strength 0 too, and after a release they couple the released clamp's host
  // triangle to every vertex around it (fill-in in each factorisation): callers whose material
  // never has the effect skip this (the cell, the fake world, `twin solve`); identification
  // registers always, as a refit may switch the effect on.
  void set_clamp_grips(const ClampSet& clamps);
  // The clamps whose jaws the clamp-slip effect lets give (clamp_slip_term.h), with the same
  // rules as set_clamp_grips. Identification registers always: at compliance 0 the springs
  // hold the patches within 0.1 micrometre per newton of where rigid clamps would.
  void set_clamp_slips(const ClampSet& clamps);
  // Every solve and differentiation with poses calls this first: it tells the clamp effects
  // which clamps are engaged and where, and returns which vertices the solver moves (those of
  // engaged clamps are held fixed, unless slip springs hold them). A clamp count that differs
  // from the registered clamps' throws std::invalid_argument.
  DofMap hold_clamps(const ClampSet& clamps, const std::vector<ClampPose>& poses) const;
  // set_clamp_grips and set_clamp_slips for the effects the material has (those it lacks get
  // no springs): for callers whose material does not change its effects.
  void set_clamps_of_material_effects(const ClampSet& clamps);
  const ClampGripTerm& clamp_grip() const { return grip_; }
  const ClampSlipTerm& clamp_slip() const { return slip_; }

  const SheetMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  int vertex_count() const { return mesh_.vertex_count(); }
  // Lumped sheet masses plus the markers' (kg).
  const std::vector<double>& vertex_masses_kg() const { return masses_; }
  double total_mass_kg() const;

  // The membrane on the mesh's (linear) triangles, whichever membrane the energy uses: its
  // elements are those the strain-rate viscosity acts on.
  const MembraneTerm& membrane() const { return membrane_; }
  // The membrane term the energy uses (quadratic when the mesh has quadratic patches).
  const EnergyTerm& membrane_energy() const {
    return quadratic_membrane_ ? static_cast<const EnergyTerm&>(*quadratic_membrane_) : membrane_;
  }
  // The hinge bending term; the energy's only with the hinge bending model.
  const BendingTerm& bending() const { return bending_; }
  BendingTerm& bending() { return bending_; }
  // The plate bending term: null unless the material's bending model is the plate.
  const PlateBendingTerm* plate_bending() const { return plate_.get(); }
  // The bending term the energy uses (hinge or plate, from the material).
  const EnergyTerm& bending_energy() const {
    return plate_ ? static_cast<const EnergyTerm&>(*plate_) : bending_;
  }
  const GravityTerm& gravity() const { return gravity_; }
  // The potential-energy terms, in a fixed order.
  std::vector<const EnergyTerm*> potential_terms() const {
    return {&membrane_energy(), &bending_energy(), &gravity_, &grip_, &slip_, &slip_.coupling()};
  }

 private:
  void apply_bending_effects(const ModelEffects& effects);
  void update_masses();
  // Throws (leaving the model as it was) if the bending term refuses the rigidities.
  void update_stiffness(const Material& material, double age_s);

  SheetMesh mesh_;
  Material material_;
  std::vector<MaterialPointLocation> markers_;
  double load_age_s_;
  std::vector<double> masses_;
  MembraneTerm membrane_;
  std::unique_ptr<QuadraticMembraneTerm> quadratic_membrane_;
  BendingTerm bending_;
  std::unique_ptr<PlateBendingTerm> plate_;
  GravityTerm gravity_;
  ClampGripTerm grip_;
  ClampSlipTerm slip_;
};

// Lumped masses (kg): a third of each triangle's mass to each of its vertices.
std::vector<double> lumped_vertex_masses(const SheetMesh& mesh, double surface_density_kg_m2);

}  // namespace twin
