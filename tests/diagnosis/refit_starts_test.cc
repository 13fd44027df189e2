// Where refits start (twin/diagnosis/refit.h): no simulation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "twin/diagnosis/effect_library.h"
#include "twin/diagnosis/refit.h"

namespace {

namespace dx = twin::diagnosis;

twin::Material base_fit() {
  twin::Material m;
  m.tensile_stiffness_u_N_m = m.tensile_stiffness_v_N_m = 6000.0;
  m.shear_stiffness_N_m = 2500.0;
  m.bending_rigidity_u_Nm = m.bending_rigidity_v_Nm = 8e-4;
  return m;
}

std::vector<double> taus_of(const std::vector<twin::Material>& starts) {
  std::vector<double> t;
  for (const twin::Material& m : starts) t.push_back(m.effects.relaxation_time_s);
  return t;
}

}  // namespace

TEST_CASE("relaxation refits start with tau spread over the stages' ages", "[diagnosis][refit]") {
  const dx::CandidateEffect& relax = dx::find_effect("viscoelastic_relaxation");
  // A one-step estimate in the score parameters' coordinates: base three, then the fraction.
  Eigen::VectorXd step = Eigen::VectorXd::Zero(4);
  step(3) = 0.9;  // fraction 0.09 (scale 0.1 per coordinate unit)

  const std::vector<double> ages = {20.0, 45.0, 300.0, 900.0};
  const std::vector<twin::Material> starts = dx::refit_starts(relax, base_fit(), step, ages);
  // Null, one step, three steps, and three taus.
  REQUIRE(starts.size() == 6);
  CHECK(starts[0].effects.relaxation_fraction == 0.0);
  CHECK(starts[1].effects.relaxation_fraction == Approx(0.09));
  const std::vector<double> taus = taus_of(starts);
  const double ratio = 900.0 / 20.0;
  CHECK(taus[3] == Approx(20.0 * std::pow(ratio, 1.0 / 6.0)));
  CHECK(taus[4] == Approx(20.0 * std::pow(ratio, 0.5)));
  CHECK(taus[5] == Approx(20.0 * std::pow(ratio, 5.0 / 6.0)));
  for (std::size_t k = 3; k < starts.size(); ++k) {
    // The one-step fraction, raised to at least 0.1 so that tau has a gradient to follow.
    CHECK(starts[k].effects.relaxation_fraction == Approx(0.1));
    CHECK(starts[k].tensile_stiffness_u_N_m == starts[1].tensile_stiffness_u_N_m);
  }

  // Without known ages, or for a candidate without tau, no tau starts.
  CHECK(dx::refit_starts(relax, base_fit(), step).size() == 3);
  Eigen::VectorXd mass_step = Eigen::VectorXd::Zero(4);
  mass_step(3) = 1.0;
  CHECK(dx::refit_starts(dx::find_effect("marker_mass"), base_fit(), mass_step, ages).size() == 3);
}

TEST_CASE("clamp grip refits also start with firm jaws at widths over the range", "[diagnosis][refit]") {
  const dx::CandidateEffect& grip = dx::find_effect("clamp_grip");
  Eigen::VectorXd step = Eigen::VectorXd::Zero(4);
  step(3) = 2.0;  // strength 0.2 (scale 0.1 per coordinate unit) at the default width
  const std::vector<twin::Material> starts = dx::refit_starts(grip, base_fit(), step);
  // Null, one step, three steps, and three widths.
  REQUIRE(starts.size() == 6);
  CHECK(starts[0].effects.clamp_grip_strength == 0.0);
  CHECK(starts[1].effects.clamp_grip_strength == Approx(0.2));
  CHECK(starts[1].effects.clamp_grip_width_m == twin::ModelEffects{}.clamp_grip_width_m);
  std::vector<double> widths;
  for (std::size_t k = 3; k < starts.size(); ++k) {
    CHECK(starts[k].effects.clamp_grip_strength == 1.0);
    CHECK(starts[k].bending_rigidity_u_Nm == base_fit().bending_rigidity_u_Nm);  // from the null start
    widths.push_back(starts[k].effects.clamp_grip_width_m);
  }
  CHECK(std::is_sorted(widths.begin(), widths.end()));
  CHECK(widths.front() < twin::ModelEffects{}.clamp_grip_width_m);
  CHECK(widths.back() <= twin::kMaxClampGripWidth_m);

  // The score test took its step at a profiled width: the one-step starts keep that width
  // (the step's strength means that grip's strength), the others do not need it.
  REQUIRE(grip.score_profile);
  CHECK(grip.score_profile->parameter == twin::MaterialParameter::kClampGripWidth);
  const double scored_width_m = grip.score_profile->values.front();
  const dx::ScoreProfilePoint scored{twin::MaterialParameter::kClampGripWidth, scored_width_m, 4};
  const std::vector<twin::Material> profiled = dx::refit_starts(grip, base_fit(), step, {}, scored);
  REQUIRE(profiled.size() == 6);
  CHECK(profiled[0].effects.clamp_grip_strength == 0.0);
  CHECK(profiled[1].effects.clamp_grip_strength == Approx(0.2));
  CHECK(profiled[1].effects.clamp_grip_width_m == scored_width_m);
  CHECK(profiled[2].effects.clamp_grip_width_m == scored_width_m);
  CHECK(profiled[3].effects.clamp_grip_width_m == starts[3].effects.clamp_grip_width_m);
}

TEST_CASE("clamp grip refits also start with firm jaws from the base fit's own start", "[diagnosis][refit]") {
  const dx::CandidateEffect& grip = dx::find_effect("clamp_grip");
  Eigen::VectorXd step = Eigen::VectorXd::Zero(4);
  step(3) = 2.0;
  // A base fit that stiffened the sheet to mimic wide jaws, and the start it left.
  twin::Material stiffened = base_fit();
  stiffened.tensile_stiffness_u_N_m = stiffened.tensile_stiffness_v_N_m = 66000.0;
  stiffened.bending_rigidity_u_Nm = stiffened.bending_rigidity_v_Nm = 2.4e-3;
  twin::Material start = base_fit();
  start.effects.clamp_grip_strength = 0.5;  // a start file may carry the effect: it is replaced

  const std::vector<twin::Material> without = dx::refit_starts(grip, stiffened, step);
  const std::vector<twin::Material> with = dx::refit_starts(grip, stiffened, step, {}, std::nullopt, start);
  REQUIRE(without.size() == 6);
  REQUIRE(with.size() == 9);
  for (std::size_t k = 0; k < without.size(); ++k) {
    CHECK(with[k].tensile_stiffness_u_N_m == without[k].tensile_stiffness_u_N_m);
    CHECK(with[k].effects.clamp_grip_width_m == without[k].effects.clamp_grip_width_m);
  }
  for (std::size_t k = 6; k < with.size(); ++k) {
    CHECK(with[k].tensile_stiffness_u_N_m == 6000.0);
    CHECK(with[k].bending_rigidity_u_Nm == 8e-4);
    CHECK(with[k].effects.clamp_grip_strength == 1.0);
    CHECK(with[k].effects.clamp_grip_width_m == with[k - 3].effects.clamp_grip_width_m);
  }
  // Other effects start from the base fit only.
  const dx::CandidateEffect& mass = dx::find_effect("marker_mass");
  Eigen::VectorXd mass_step = Eigen::VectorXd::Zero(4);
  mass_step(3) = 1.0;
  CHECK(dx::refit_starts(mass, stiffened, mass_step, {}, std::nullopt, start).size() ==
        dx::refit_starts(mass, stiffened, mass_step).size());
}

TEST_CASE("profiled score values lie in their parameter's range", "[diagnosis][effects]") {
  for (const dx::CandidateEffect& e : dx::effect_library()) {
    if (!e.score_profile) continue;
    INFO(e.name);
    const twin::ParameterScale scale = twin::parameter_scale(e.score_profile->parameter);
    CHECK(e.score_profile->values.size() >= 2);
    for (double v : e.score_profile->values) {
      CHECK(v >= scale.lower);
      CHECK(v <= scale.upper);
    }
    // Not one of the parameters the test differentiates: it is held at each value.
    CHECK(std::find(e.score_parameters.begin(), e.score_parameters.end(), e.score_profile->parameter) ==
          e.score_parameters.end());
  }
}
