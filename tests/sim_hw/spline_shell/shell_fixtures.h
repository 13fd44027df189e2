#pragma once
// What the reference shell's tests share: the lab composite in the shell's terms, and uniform
// spline patches.

#include <vector>

#include "sim_hw/real_sheet/sheet_material.h"
#include "sim_hw/spline_shell/spline_patch.h"

namespace shell_fixtures {

// An orthotropic composite: 6000 / 3000 N/m tensile, 2500 N/m shear, nu 0.3, bending 8e-4 /
// bending_v N*m (Huber's D12, D66), 0.3 kg/m^2.
inline sim_hw::real_sheet::SheetMaterial composite(double bending_v_Nm = 5e-4) {
  twin::Material m;
  m.tensile_stiffness_u_N_m = 6000;
  m.tensile_stiffness_v_N_m = 3000;
  m.shear_stiffness_N_m = 2500;
  m.poisson_ratio = 0.3;
  m.bending_rigidity_u_Nm = 8e-4;
  m.bending_rigidity_v_Nm = bending_v_Nm;
  m.surface_density_kg_m2 = 0.3;
  return sim_hw::real_sheet::sheet_material_from(m);
}

inline sim_hw::spline_shell::SplinePatch uniform_patch(int degree, int elements_u, int elements_v, double width_m,
                                                       double height_m) {
  std::vector<double> bu, bv;
  for (int e = 0; e <= elements_u; ++e) bu.push_back(width_m * e / elements_u);
  for (int e = 0; e <= elements_v; ++e) bv.push_back(height_m * e / elements_v);
  return sim_hw::spline_shell::SplinePatch(sim_hw::spline_shell::KnotVector(degree, bu),
                                           sim_hw::spline_shell::KnotVector(degree, bv));
}

}  // namespace shell_fixtures
