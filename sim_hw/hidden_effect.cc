#include "sim_hw/hidden_effect.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace sim_hw {
namespace {

// Streams of derived_seed, one per use.
constexpr std::uint64_t kChoiceStream = 0x636f6963ULL, kMagnitudeStream = 0x6d61676eULL;

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Uniform draws defined here rather than by std:: distributions, whose output differs between
// standard libraries: a seed must make the same set everywhere.
class Draws {
 public:
  explicit Draws(std::uint64_t seed) : state_(seed) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(splitmix64(state_) >> 11) * 0x1.0p-53;
  }
  double sign() { return uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0; }

 private:
  std::uint64_t state_;
};

constexpr double kDegree = std::numbers::pi / 180.0;

void orthotropic(HiddenEffect& h, Draws& d) {
  // Warp (v) over weft (u): either clearly softer or clearly stiffer. Stiffer stops at 2.5: hinge
  // bending on the offset-row meshes of 100-300 triangles represents warp/weft up to about 2.6
  // only (BendingCalibration refuses more), and the twin must be able to hold the truth.
  const double bending_ratio = d.uniform(0.0, 1.0) < 0.5 ? d.uniform(0.3, 0.6) : d.uniform(1.7, 2.5);
  const double tensile_ratio = std::exp(d.uniform(std::log(0.5), std::log(2.0)));
  twin::Material& m = h.truth;
  const double bending = std::sqrt(m.bending_rigidity_u_Nm * m.bending_rigidity_v_Nm);
  const double tensile = std::sqrt(m.tensile_stiffness_u_N_m * m.tensile_stiffness_v_N_m);
  m.bending_rigidity_u_Nm = bending / std::sqrt(bending_ratio);
  m.bending_rigidity_v_Nm = bending * std::sqrt(bending_ratio);
  m.tensile_stiffness_u_N_m = tensile / std::sqrt(tensile_ratio);
  m.tensile_stiffness_v_N_m = tensile * std::sqrt(tensile_ratio);
  h.parameters = {{"bending_u_Nm", m.bending_rigidity_u_Nm},    {"bending_v_Nm", m.bending_rigidity_v_Nm},
                  {"tensile_u_N_m", m.tensile_stiffness_u_N_m}, {"tensile_v_N_m", m.tensile_stiffness_v_N_m},
                  {"warp_weft_bending_ratio", bending_ratio},   {"warp_weft_tensile_ratio", tensile_ratio}};
  h.description = fmt::format("orthotropic: warp/weft bending ratio {:.2f}, tensile ratio {:.2f}", bending_ratio,
                              tensile_ratio);
}

void rest_curvature(HiddenEffect& h, Draws& d) {
  const double radius_m = d.uniform(0.3, 1.5);
  const double direction = d.uniform(0.0, 180.0) * kDegree;
  const double kappa = d.sign() / radius_m;
  const double c = std::cos(direction), s = std::sin(direction);
  // Rolled about the line perpendicular to the direction: K0 = kappa t t^T, t = (cos, sin).
  twin::ModelEffects& e = h.truth.effects;
  e.rest_curvature_uu_1_m = kappa * c * c;
  e.rest_curvature_vv_1_m = kappa * s * s;
  e.rest_curvature_uv_1_m = kappa * c * s;
  h.parameters = {{"rest_curvature_uu_1_m", e.rest_curvature_uu_1_m},
                  {"rest_curvature_vv_1_m", e.rest_curvature_vv_1_m},
                  {"rest_curvature_uv_1_m", e.rest_curvature_uv_1_m},
                  {"roll_radius_m", radius_m},
                  {"roll_direction_deg", direction / kDegree}};
  h.description = fmt::format("roll set: radius {:.2f} m, curving along {:.0f} deg from weft", radius_m,
                              direction / kDegree);
}

void nonlinear_bending(HiddenEffect& h, Draws& d, double typical_curvature_1_m) {
  if (!(typical_curvature_1_m > 0.0) || !std::isfinite(typical_curvature_1_m)) {
    throw std::runtime_error(fmt::format("hidden effect: typical curvature {} 1/m is not positive", typical_curvature_1_m));
  }
  const double product = d.uniform(0.5, 3.0);  // beta kappa^2 at the typical curvature
  h.truth.effects.bending_stiffening_m2 = product / (typical_curvature_1_m * typical_curvature_1_m);
  h.parameters = {{"bending_stiffening_m2", h.truth.effects.bending_stiffening_m2},
                  {"typical_curvature_1_m", typical_curvature_1_m},
                  {"beta_kappa2_at_typical", product}};
  h.description = fmt::format("bending stiffens with curvature: beta kappa^2 = {:.2f} at kappa = {:.2f} 1/m",
                              product, typical_curvature_1_m);
}

}  // namespace

const std::vector<std::string>& blind_effect_names() {
  static const std::vector<std::string> names = {"none",           "orthotropic_stiffness",   "rest_curvature",
                                                 "nonlinear_bending", "marker_mass", "viscoelastic_relaxation",
                                                 "clamp_grip",        "clamp_slip",  "outside_library"};
  return names;
}

std::uint64_t derived_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t state = seed ^ (stream * 0xd1342543de82ef95ULL);
  splitmix64(state);
  return splitmix64(state);
}

std::string effect_for_seed(std::uint64_t seed) {
  const auto& names = blind_effect_names();
  // 53 random bits to one of 9: the bias is far below anything a few hundred seeds could show.
  Draws d(derived_seed(seed, kChoiceStream));
  const auto index = static_cast<std::size_t>(d.uniform(0.0, static_cast<double>(names.size())));
  return names[std::min(index, names.size() - 1)];
}

HiddenEffect draw_hidden_effect(std::uint64_t seed, const std::string& effect, const LabSpecimen& specimen,
                                const std::function<double()>& typical_curvature_1_m) {
  const auto& names = blind_effect_names();
  if (std::find(names.begin(), names.end(), effect) == names.end()) {
    throw std::invalid_argument(fmt::format("unknown hidden effect '{}' (expected one of: {})", effect,
                                            fmt::join(names, ", ")));
  }
  HiddenEffect h;
  h.effect = effect;
  h.truth = specimen.truth;
  Draws d(derived_seed(seed, kMagnitudeStream));
  twin::ModelEffects& e = h.truth.effects;
  if (effect == "none") {
    h.description = "no hidden effect: the specimen's own material";
  } else if (effect == "orthotropic_stiffness") {
    orthotropic(h, d);
  } else if (effect == "rest_curvature") {
    rest_curvature(h, d);
  } else if (effect == "nonlinear_bending") {
    nonlinear_bending(h, d, typical_curvature_1_m());
  } else if (effect == "marker_mass") {
    e.marker_mass_kg = d.uniform(0.5e-3, 2e-3);
    h.parameters = {{"marker_mass_kg", e.marker_mass_kg}};
    h.description = fmt::format("markers weigh {:.2f} g each", e.marker_mass_kg * 1e3);
  } else if (effect == "viscoelastic_relaxation") {
    e.relaxation_fraction = d.uniform(0.3, 0.6);
    e.relaxation_time_s = d.uniform(60.0, 600.0);
    h.parameters = {{"relaxation_fraction", e.relaxation_fraction}, {"relaxation_time_s", e.relaxation_time_s}};
    h.description = fmt::format("stiffness relaxes by {:.0f} % with tau = {:.0f} s after each clamp move",
                                100.0 * e.relaxation_fraction, e.relaxation_time_s);
  } else if (effect == "clamp_grip") {
    e.clamp_grip_width_m = d.uniform(0.02, 0.06);
    e.clamp_grip_strength = std::exp(d.uniform(std::log(0.3), std::log(1.5)));
    h.parameters = {{"clamp_grip_strength", e.clamp_grip_strength}, {"clamp_grip_width_m", e.clamp_grip_width_m}};
    h.description = fmt::format("the clamps' jaws grip {:.0f} mm further out than the trial files say, strength {:.2f}",
                                e.clamp_grip_width_m * 1e3, e.clamp_grip_strength);
  } else if (effect == "clamp_slip") {
    e.clamp_slip_compliance_m_N = std::exp(d.uniform(std::log(1e-4), std::log(1e-3)));
    h.parameters = {{"clamp_slip_compliance_m_N", e.clamp_slip_compliance_m_N}};
    h.description = fmt::format("the ply slips in the clamps' jaws by {:.1f} mm per newton of pull along them",
                                e.clamp_slip_compliance_m_N * 1e3);
  } else {  // outside_library
    // Folded in four for storage: the two folds cross at right angles, at a random turn.
    const twin::Vec2 point(d.uniform(0.35, 0.65) * specimen.width_m, d.uniform(0.35, 0.65) * specimen.height_m);
    const double direction = d.uniform(0.0, 90.0) * kDegree;
    for (int k = 0; k < 2; ++k) {
      Crease c;
      c.point_m = point;
      c.direction_rad = direction + k * 90.0 * kDegree;
      c.angle_rad = d.sign() * d.uniform(40.0, 80.0) * kDegree;
      h.creases.push_back(c);
      const std::string name = fmt::format("crease_{}_", k + 1);
      h.parameters.insert(h.parameters.end(), {{name + "direction_deg", c.direction_rad / kDegree},
                                               {name + "angle_deg", c.angle_rad / kDegree}});
    }
    h.parameters.insert(h.parameters.begin(), {{"crease_point_u_m", point.x()}, {"crease_point_v_m", point.y()}});
    h.description = fmt::format("folded in four: creases of {:.0f} and {:.0f} deg through ({:.2f}, {:.2f}) m, the "
                                "first at {:.0f} deg from weft",
                                h.creases[0].angle_rad / kDegree, h.creases[1].angle_rad / kDegree, point.x(),
                                point.y(), direction / kDegree);
  }
  h.truth.validate();
  return h;
}

}  // namespace sim_hw
