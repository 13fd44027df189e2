#pragma once
// The scanner lab's specimens (paper section 5.1, Tables 3-4): sheet size, thickness, mass, and
// the lab's own "true" material, which identification must never read. Densities come from
// mass / area (the paper's Table 3 lists felt at 0.0018 kg/m^2, a typo for 0.178).
//
// The stiffness figures are the lab's choice of plausible values, not measurements: they are
// what the reference sheet is simulated with, so identification has a truth to recover.

#include <string>
#include <vector>

#include "twin/model/material.h"

namespace sim_hw {

struct LabSpecimen {
  std::string name;              // composite, cloth, canvas, felt
  double width_m = 0.0, height_m = 0.0, thickness_m = 0.0, mass_kg = 0.0;
  twin::Material truth;          // surface density = mass / area
};

const std::vector<std::string>& lab_specimen_names();
// Throws std::invalid_argument listing the valid names.
LabSpecimen lab_specimen(const std::string& name);

}  // namespace sim_hw
