#pragma once
// The sheet's material as one homogeneous CalculiX shell section. A homogeneous shell of
// thickness t and plane-stress stiffness Q has membrane stiffness Q t (N/m) and bending
// rigidity Q t^3 / 12 (N*m): its bending and membrane are tied, the sheet's are not. The
// section matches the bending exactly (D11, D22, D12 and D66: folds and drape are bending's), and
// the membrane's tensile stiffness along u (t = sqrt(12 D11 / C11)); the membrane's other terms
// then follow from the bending, and the section says by how much they differ from the
// material's (a ply's membrane is so much stiffer than gravity's loads that its strains, not its
// shape, are what this changes). Transverse shear is as stiff as in-plane shear, and the
// thickness is decoupled from the plane (nu13 = nu23 = 0) so the expanded shell is in plane stress.

#include <string>

#include "twin/model/material.h"

namespace sim_hw::calculix {

struct ShellSection {
  double thickness_m = 0;
  double density_kg_m3 = 0;  // surface density / t
  bool isotropic = true;     // then *ELASTIC with E1 and nu12
  double e1_Pa = 0, e2_Pa = 0, nu12 = 0, g12_Pa = 0;
  // The section's membrane terms over the material's: C22, C12 and C66 (C11's is 1).
  double membrane_v_ratio = 1, membrane_coupling_ratio = 1, membrane_shear_ratio = 1;
  std::string text() const;  // one line for the tool's header
};

// Throws std::invalid_argument for a material with an effect this section has no form of (the
// paper's model only: no rest curvature, stiffening, relaxation, marker masses or jaw effects),
// naming the effect.
ShellSection shell_section(const twin::Material& material);

}  // namespace sim_hw::calculix
