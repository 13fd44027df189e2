#include "sim_hw/lab_materials.h"

#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace sim_hw {
namespace {

LabSpecimen make(const std::string& name, double w, double h, double t, double mass, double tensile,
                 double shear, double bending) {
  LabSpecimen s;
  s.name = name;
  s.width_m = w;
  s.height_m = h;
  s.thickness_m = t;
  s.mass_kg = mass;
  s.truth.name = name + " (scanner lab truth)";
  s.truth.surface_density_kg_m2 = mass / (w * h);
  s.truth.tensile_stiffness_u_N_m = s.truth.tensile_stiffness_v_N_m = tensile;
  s.truth.shear_stiffness_N_m = shear;
  s.truth.bending_rigidity_u_Nm = s.truth.bending_rigidity_v_Nm = bending;
  s.truth.poisson_ratio = 0.3;
  s.truth.thickness_m = t;
  return s;
}

}  // namespace

const std::vector<std::string>& lab_specimen_names() {
  static const std::vector<std::string> names = {"composite", "cloth", "canvas", "felt"};
  return names;
}

LabSpecimen lab_specimen(const std::string& name) {
  // Composite: Table 4 (1.17 x 0.975 m, 0.3 mm, 0.3 kg/m^2). Fabrics: Table 3 sizes and masses.
  if (name == "composite") return make(name, 1.17, 0.975, 0.3e-3, 0.3 * 1.17 * 0.975, 6000.0, 2500.0, 8e-4);
  if (name == "cloth") return make(name, 0.611, 0.611, 0.1e-3, 42.1e-3, 2000.0, 300.0, 2e-5);
  if (name == "canvas") return make(name, 0.613, 0.613, 0.65e-3, 168.9e-3, 9000.0, 1500.0, 4e-4);
  if (name == "felt") return make(name, 0.615, 0.612, 1.8e-3, 66.9e-3, 1500.0, 800.0, 3e-4);
  throw std::invalid_argument(fmt::format("unknown lab specimen '{}' (expected one of: {})", name,
                                          fmt::join(lab_specimen_names(), ", ")));
}

}  // namespace sim_hw
