#pragma once
// What the independent sheet is made of, in its own terms: a Kirchhoff-Love plate with an
// orthotropic St. Venant-Kirchhoff membrane and a full orthotropic bending matrix, plus the
// physics the scanner lab's hidden effects add, each in this model's own form (none of them
// calls or copies a twin effect term).
//
// Membrane: energy density (J/m^2) 1/2 e^T C e on the Green-Lagrange strain
//   e = (E_uu, E_vv, 2 E_uv), C (N/m) the orthotropic plane-stress matrix of the material file's
//   tensile stiffnesses Y_u, Y_v, Poisson ratio nu and shear stiffness G (docs/file_formats.md, "Material file").
// Bending: energy density 1/2 k^T D k (1 + beta/2 |k|^2) on the curvature change
//   k = (k_uu, k_vv, 2 k_uv) - rest, k_ab = x_,ab . n (the second fundamental form in material
//   coordinates), D = [[D11, D12, 0], [D12, D22, 0], [0, 0, D66]] (N*m), |k|^2 = k_uu^2 + k_vv^2
//   + 2 k_uv^2. From a twin material file: D11 = D_u, D22 = D_v and Huber's orthotropic plate,
//   D12 = nu sqrt(D11 D22), D66 = (1 - nu)/2 sqrt(D11 D22), which is the isotropic plate when
//   D_u = D_v. A laminate's own D12 and D66 can be given instead.
// Effects in this model's form:
//   rest curvature         K0 (1/m) in the material frame, uniform, plus creases: bands of
//                          concentrated rest curvature (a fold's angle spread over a width).
//   bending stiffening     beta (m^2) above: isotropic in the curvature, not per hinge.
//   marker mass            point masses (kg) at the markers' material points.
//   relaxation (creep)     under constant load the matrix creeps: shear and bending (the
//                          resin-dominated stiffnesses, not the fibres' tensile) are divided by
//                          1 + phi (1 - exp(-age / tau)) with phi = f / (1 - f), f the long-term
//                          loss; a retardation law, not the twin's relaxation factor.
//   wide jaws              the jaw pads reach `pad_extension_m` beyond the grip radius, their hold
//                          there falling off as a Hertzian contact pressure,
//                          strength sqrt(1 - (rho / R)^2) over the annulus.
//   slipping jaws          the jaw faces hold the ply with a tangential compliance (m/N for the
//                          whole pad), so the ply slides and shears in the jaws under pull.

#include <vector>

#include <Eigen/Core>

#include "sim_hw/real_sheet/grid.h"
#include "twin/model/material.h"

namespace sim_hw::real_sheet {

constexpr double kGravity_m_s2 = 9.80665;

// A crease: the ply was once folded by angle_rad across the line through point_m along
// direction_rad (from u). Its rest curvature, across the line, spreads the angle over
// width_m with a raised-cosine profile.
struct CreaseBand {
  Vec2 point_m = Vec2::Zero();
  double direction_rad = 0.0;
  double angle_rad = 0.0;
  double width_m = 0.015;
};

struct SheetMaterial {
  double density_kg_m2 = 0.3;
  Eigen::Matrix3d membrane_C_N_m = Eigen::Matrix3d::Identity();  // on (E_uu, E_vv, 2 E_uv)
  double D11_Nm = 1e-3, D22_Nm = 1e-3, D12_Nm = 3e-4, D66_Nm = 3.5e-4;
  double tensile_viscosity_Ns_m = 0, shear_viscosity_Ns_m = 0, mass_damping_1_s = 0;
  Eigen::Matrix2d rest_curvature_1_m = Eigen::Matrix2d::Zero();  // symmetric, material frame
  std::vector<CreaseBand> creases;
  double stiffening_m2 = 0;  // beta
  double marker_mass_kg = 0;
  double creep_fraction = 0, creep_time_s = 60;  // f in [0, 1), tau > 0
  double pad_extension_m = 0, pad_strength = 0;  // wide jaws (strength 0: absent)
  double slip_compliance_m_N = 0;                // slipping jaws (0: absent)

  Eigen::Matrix3d bending_D_Nm() const;
  // Factor on shear and bending stiffness `age_s` after the clamps last moved (NaN: long after).
  double creep_factor(double age_s) const;
};

// The independent model's reading of a twin material file: its constants, and its effects block
// mapped onto this model's own forms of the same physics (see above).
SheetMaterial sheet_material_from(const twin::Material& material);

// Rest curvature (k_uu, k_vv, 2 k_uv) at a material point: uniform K0 plus the creases' bands.
Eigen::Vector3d rest_curvature_at(const SheetMaterial& material, const Vec2& uv_m);

}  // namespace sim_hw::real_sheet
