#pragma once
// The sheet's material as one homogeneous CalculiX shell section. A homogeneous shell of
// thickness t and plane-stress stiffness Q has membrane stiffness Q t (N/m) and bending
// rigidity Q t^3 / 12 (N*m): its bending and membrane are tied, the sheet's are not. The
// section matches D11, D22, D12 and the membrane's tensile stiffness along u (t = sqrt(12 D11 /
// C11)); the in-plane shear modulus then matches either the bending's twist D66 (folds and
// drape are bending's) or the membrane's shear C66 (a taut sheet's shape is its membrane's: on
// the taut example the membrane's 8 % moved the markers 0.1 mm), and the section says by how much
// the other terms differ from the material's. Transverse shear is as stiff as in-plane shear, and the
// thickness is decoupled from the plane (nu13 = nu23 = 0) so the expanded shell is in plane stress.

#include <string>

#include "twin/model/material.h"

namespace sim_hw::calculix {

enum class ShearFrom { kBending, kMembrane };

struct ShellSection {
  double thickness_m = 0;
  double density_kg_m3 = 0;  // surface density / t
  bool isotropic = true;     // then *ELASTIC with E1 and nu12
  double e1_Pa = 0, e2_Pa = 0, nu12 = 0, g12_Pa = 0;
  // The section's membrane terms over the material's: C22, C12 and C66 (C11's is 1); and its
  // twist rigidity D66 over the material's.
  double membrane_v_ratio = 1, membrane_coupling_ratio = 1, membrane_shear_ratio = 1, twist_ratio = 1;
  std::string text() const;  // one line for the tool's header
};

// Throws std::invalid_argument for a material with an effect this section has no form of (the
// paper's model only: no rest curvature, stiffening, relaxation, marker masses or jaw effects),
// naming the effect.
ShellSection shell_section(const twin::Material& material, ShearFrom shear = ShearFrom::kBending);

}  // namespace sim_hw::calculix
