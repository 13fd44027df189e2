// The discrepancy workflow on the cell's own states (cell/learning/in_situ_diagnosis.h), on
// states of the fake world's independent sheet: the split into fitted and held-out trials, a
// hidden effect named and put into the twin only because it predicts the held-out state better,
// nothing named where nothing is missing, and a diagnosis that stops when told.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "cell/learning/cell_trial.h"
#include "cell/learning/in_situ_diagnosis.h"
#include "tests/cell/learning/independent_states.h"
#include "tests/support/temp_dir.h"

using cell::learning::EffectAdoption;
using testing_support::lab_material;

namespace {

constexpr int kTwinTriangles = 300;

struct States {
  testing_support::TempDir dir{"in_situ_diagnosis"};
  twin::Trial trial;
  States(const twin::Material& truth, double sigma_m, sim_hw::TruthModel model = sim_hw::TruthModel::kIndependent) {
    // The twin's own model on the twin's own mesh (kTwin), or the independent sheet on a 3 cm grid.
    const double grid_m =
        model == sim_hw::TruthModel::kTwin ? twin::edge_length_for_triangle_count(0.6, 0.5, kTwinTriangles) : 0.03;
    const auto data = testing_support::independent_states(truth, kTwinTriangles, grid_m, sigma_m, 3, model);
    trial = cell::learning::write_cell_trial((dir / "trial").string(), data.states, data.twin_mesh, data.plan, truth);
  }
};

}  // namespace

TEST_CASE("the diagnosis fits every state but the newest and scores the newest after the clamps' whole path") {
  States s(lab_material(6000, 2500, 8e-4), 0.0005);
  REQUIRE(s.trial.stages.size() == 4);
  cell::learning::write_diagnosis_trials(s.trial, (s.dir / "split").string());
  const twin::Trial train = twin::read_trial((s.dir / "split" / "train").string());
  const twin::Trial held_out = twin::read_trial((s.dir / "split" / "held_out").string());
  REQUIRE(train.stages.size() == 3);
  REQUIRE(held_out.stages.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) {
    // The clamps' path is the observed trial's in both.
    for (std::size_t c = 0; c < s.trial.clamps.size(); ++c) {
      CHECK(held_out.stages[k].poses[c].position_m.isApprox(s.trial.stages[k].poses[c].position_m));
      if (k < 3) CHECK(train.stages[k].poses[c].position_m.isApprox(s.trial.stages[k].poses[c].position_m));
    }
    const int seen = held_out.stages[k].observed.seen_marker_count();
    if (k < 3) {
      CHECK(seen == 0);  // followed, not scored
      CHECK(train.stages[k].observed.seen_marker_count() == s.trial.stages[k].observed.seen_marker_count());
    } else {
      CHECK(seen == s.trial.stages[k].observed.seen_marker_count());
    }
  }
  twin::Trial two = s.trial;
  two.stages.resize(2);
  CHECK_THROWS_WITH(cell::learning::write_diagnosis_trials(two, (s.dir / "two").string()),
                    Catch::Contains("2 settled state(s)"));
}

TEST_CASE("a diagnosis told to stop ends without a verdict and adopts nothing") {
  States s(lab_material(6000, 2500, 8e-4), 0.0005);
  cell::learning::DiagnosisOptions options;
  options.cancelled = [] { return true; };
  const auto r = cell::learning::diagnose_states(s.trial, lab_material(6000, 2500, 8e-4), (s.dir / "d").string(), options);
  INFO(r.reason);
  CHECK_FALSE(r.ran);
  CHECK(r.adoption == EffectAdoption::kFailed);
  CHECK_THAT(r.reason, Catch::Contains("cancelled"));
  CHECK(r.material_file.empty());
}

// The cell's plumbing from a named effect to the twin: split, diagnose, judge, adopt. Warp and
// weft bend differently (a fabric's yarns): the paper's isotropic model cannot take it, the
// orthotropic candidate can. The states are the twin's own shell model on the cell twin's own
// mesh: on the independent sheet the 300-triangle twin misses by 10 mm mean whatever the material
// (next test), and so does it the same model on a 3 cm grid (7 mm: a slack sheet's equilibria
// move with the mesh), which no candidate explains; so naming is tested where the twin can follow
// the sheet. Plumbing, not accuracy. The cell starts from a wrong isotropic material.
TEST_CASE("an effect hidden in the states is named, and adopted only because it predicts the held-out state better") {
  twin::Material truth = lab_material(6000, 2500, 2e-3);
  truth.bending_rigidity_v_Nm = 2e-4;
  States s(truth, 0.0005, sim_hw::TruthModel::kTwin);
  cell::learning::DiagnosisOptions options;
  options.effects = "orthotropic_stiffness,clamp_slip";
  options.noise_mm = 0.5;
  options.base_evaluations = options.refit_evaluations = 40;
  const auto r = cell::learning::diagnose_states(s.trial, lab_material(6000, 2500, 8e-4), (s.dir / "d").string(), options);
  INFO(r.reason);
  INFO(r.outcome.summary_text);
  REQUIRE(r.ran);
  for (const std::string& why : r.outcome.verdict.reasons) UNSCOPED_INFO(why);
  CHECK(r.outcome.verdict.verdict == "effect");
  REQUIRE(r.outcome.verdict.effect.has_value());
  CHECK(*r.outcome.verdict.effect == "orthotropic_stiffness");
  CHECK(std::filesystem::exists(s.dir / "d" / "report" / "report.md"));
  CHECK(std::filesystem::exists(s.dir / "d" / "report" / "verdict.json"));
  // The wrong isotropic start predicts the held-out state far worse than the base fit with the
  // effect: adopted, and the judge's numbers say why.
  CHECK(r.adoption == EffectAdoption::kAdopted);
  CHECK(r.after.held_out_mean_m < 0.9 * r.before.held_out_mean_m);
  CHECK(r.augmented.bending_rigidity_u_Nm > 2.0 * r.augmented.bending_rigidity_v_Nm);
  CHECK(std::filesystem::exists(r.material_file));

  // The same named effect against a cell that already runs the true material: no better on the
  // held-out state, so refused, and no material file is handed on.
  const auto judged_only = cell::learning::judge_material(s.trial, truth, r.augmented);
  INFO(judged_only.reason);
  CHECK(judged_only.verdict == cell::learning::CalibrationVerdict::kRefused);
}

// The independent sheet with nothing hidden: the twin misses it by about 10 mm mean (its
// resolution and the sheet's, branches of a slack sheet), which is no effect of the library.
// Whatever the verdict calls that, no effect may be named and the cell keeps its material.
TEST_CASE("on the independent sheet with no effect hidden, the diagnosis names none and the cell keeps its material") {
  const twin::Material truth = lab_material(6000, 2500, 8e-4);
  States s(truth, 0.002);
  cell::learning::DiagnosisOptions options;
  options.effects = "orthotropic_stiffness,clamp_slip";
  options.noise_mm = 2.0;
  const auto r = cell::learning::diagnose_states(s.trial, truth, (s.dir / "d").string(), options);
  INFO(r.reason);
  INFO(r.outcome.summary_text);
  REQUIRE(r.ran);
  CHECK(r.outcome.verdict.verdict != "effect");
  CHECK(r.adoption == EffectAdoption::kNotNamed);
  CHECK(r.material_file.empty());
  CHECK_FALSE(std::filesystem::exists(s.dir / "d" / "report" / "material_augmented.json"));
}
