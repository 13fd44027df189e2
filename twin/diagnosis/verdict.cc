#include "twin/diagnosis/verdict.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "twin/diagnosis/chi_square.h"
#include "twin/diagnosis/effect_library.h"
#include "twin/diagnosis/residual_analysis.h"

namespace twin::diagnosis {

ResidualTest residual_test(const SetScore& set, int fitted_parameters, double sigma_m, double sigma_relative_error) {
  ResidualTest t;
  if (set.residual_count == 0) return t;
  t.chi_square = set.sum_squares_m2 / (sigma_m * sigma_m);
  t.dof = std::max(1, set.residual_count - fitted_parameters);
  t.p_value = chi_square_upper_tail(t.chi_square, t.dof);
  t.rms_ratio = std::sqrt(t.chi_square / t.dof);
  t.significant = t.p_value < kResidualAlpha && t.rms_ratio > kNoiseTolerance * (1.0 + 2.0 * sigma_relative_error);
  return t;
}

namespace {

const CandidateScore* score_of(const std::vector<CandidateScore>& scores, const std::string& effect) {
  for (const CandidateScore& s : scores) {
    if (s.effect == effect) return &s;
  }
  return nullptr;
}

// Whether the refit's own intervals say the effect is there: some strength of it (every added
// parameter but a relaxation time or a grip width, which mean nothing while the effect is
// absent) has a 95 % interval that excludes its value in null_material(). A refit that lowers
// the misfit with every strength compatible with "absent" has found something else (seen: a
// null set whose base fit left one training stage on a neighbouring equilibrium, "explained" by
// a relaxation of 1.7 % [-0.8, 4.1] % because the refit's fresh simulation found the
// right branch). With no strength parameter (a refit without estimates), nothing to check.
bool strength_supported(const Refit& r, std::string& evidence) {
  const auto& library = effect_library();
  const auto effect = std::find_if(library.begin(), library.end(),
                                   [&](const CandidateEffect& c) { return c.name == r.effect; });
  if (effect == library.end()) return true;  // not a library effect: nothing to compare with
  const Material null = null_material(*effect, r.result.material);
  bool any = false;
  for (const ParameterEstimate& e : r.effect_estimates) {
    if (e.parameter == MaterialParameter::kRelaxationTime || e.parameter == MaterialParameter::kClampGripWidth) continue;
    any = true;
    const double absent = get_parameter(null, e.parameter);
    if (absent < e.lower95 || absent > e.upper95) return true;
    evidence += fmt::format("{}{} [{:.4g}, {:.4g}] contains {:.4g}", evidence.empty() ? "" : "; ",
                            parameter_name(e.parameter), e.lower95, e.upper95, absent);
  }
  return !any;
}

// How much of the base fit's gap (its mean marker error above the noise floor) a refit takes on
// one set. Judged only where the base residual is significant and its mean is above the floor;
// elsewhere the gap is noise and its share means nothing.
struct GapTaken {
  bool judged = false;
  double share = 0.0;
  bool enough = true;
  std::string describe() const { return judged ? fmt::format("{:.0f} %", 100.0 * share) : std::string("-"); }
};

GapTaken gap_taken(const SetScore& base, const SetScore& refit, bool base_significant, double floor_m) {
  GapTaken g;
  const double gap_m = base.mean_correspondence_m - floor_m;
  if (!base_significant || refit.residual_count == 0 || !(gap_m > 0.0)) return g;
  g.judged = true;
  g.share = (base.mean_correspondence_m - refit.mean_correspondence_m) / gap_m;
  g.enough = g.share >= kMinGapExplained;
  return g;
}

}  // namespace

Verdict decide(const SetScore& base_train, const SetScore& base_test, double base_bic,
               const std::vector<CandidateScore>& scores, const std::vector<Refit>& refits, double sigma_m,
               double sigma_relative_error, std::optional<double> discretisation_m) {
  Verdict v;
  const bool measured = discretisation_m && std::isfinite(*discretisation_m);
  const double d = measured ? std::max(*discretisation_m, 0.0) : 0.0;
  v.budget_m = std::hypot(sigma_m, d);
  const ResidualTest train = residual_test(base_train, 3, sigma_m, sigma_relative_error);
  const ResidualTest test = residual_test(base_test, 0, sigma_m, sigma_relative_error);
  auto describe = [](const char* set, const ResidualTest& t) {
    return fmt::format("{} residual of the base fit: RMS {:.2f} x sigma, chi-square {:.0f} on {:.0f} dof, p = {:.2g}{}",
                       set, t.rms_ratio, t.chi_square, t.dof, t.p_value, t.significant ? " (significant)" : "");
  };
  v.reasons.push_back(describe("training", train));
  if (base_test.residual_count > 0) v.reasons.push_back(describe("held-out", test));
  if (!train.significant && !test.significant) {
    v.verdict = "none";
    v.summary = fmt::format("no missing effect supported: the base fit's residual is within the noise floor "
                            "(RMS {:.2f} / {:.2f} x sigma, train / held-out)",
                            train.rms_ratio, test.rms_ratio);
    return v;
  }

  int tested = 0;
  for (const CandidateScore& s : scores) tested += s.skipped.empty() ? 1 : 0;
  const double alpha = kScoreAlpha / std::max(tested, 1);
  const Refit* best = nullptr;
  const Refit* closest = nullptr;
  for (const Refit& r : refits) {
    if (!r.usable()) {
      v.reasons.push_back(fmt::format("{}: refit failed ({})", r.effect, r.failure));
      continue;
    }
    if (!closest || r.test.sum_squares_m2 < closest->test.sum_squares_m2) closest = &r;
    const CandidateScore* s = score_of(scores, r.effect);
    const bool score_ok = s && s->skipped.empty() && s->score.p_value < alpha;
    const bool bic_ok = r.information_criterion < base_bic;
    const bool held_out_ok = !(r.test.mean_correspondence_m >= base_test.mean_correspondence_m);
    std::string absent_evidence;
    const bool strength_ok = strength_supported(r, absent_evidence);
    // What the refit removed against what it could have taken of the twin's own discretisation
    // error: the part of the residual's change to a finer twin in the effect's span
    // (absorbable_m2; sums of squares). Were the data's effect and that part aligned, the refit
    // would remove (a + b)^2 with a the effect's and b the absorbable norm; more than (2 b)^2
    // means a > b. Without the projection: more than d RMS per coordinate.
    const double gain_m2 = std::max(0.0, base_train.sum_squares_m2 - r.train.sum_squares_m2);
    const bool projected = s && s->score.absorbable_m2 >= 0.0;
    const double could_m2 = projected ? 4.0 * s->score.absorbable_m2
                                      : d * d * static_cast<double>(std::max(base_train.residual_count, 1));
    const bool beyond_discretisation = !(d > 0.0) || gain_m2 > could_m2;
    const double per_coordinate = 1.0 / static_cast<double>(std::max(base_train.residual_count, 1));
    const bool qualifies = score_ok && bic_ok && held_out_ok && strength_ok && beyond_discretisation;
    v.reasons.push_back(fmt::format(
        "{}: score p = {:.2g} (needs < {:.2g}), BIC {:+.1f} vs base, held-out mean {:.3f} -> {:.3f} mm{}{}{}", r.effect,
        s ? s->score.p_value : 1.0, alpha, r.information_criterion - base_bic, 1e3 * base_test.mean_correspondence_m,
        1e3 * r.test.mean_correspondence_m,
        strength_ok ? "" : fmt::format(", its fitted strength is compatible with absent ({})", absent_evidence),
        beyond_discretisation
            ? ""
            : fmt::format(", it removes {:.3f} mm RMS, no more than it could take of the twin's discretisation "
                          "error ({:.3f} mm{})",
                          1e3 * std::sqrt(gain_m2 * per_coordinate), 1e3 * std::sqrt(could_m2 * per_coordinate),
                          projected ? ": twice the part of it in the effect's span" : ""),
        qualifies ? " (qualifies)" : ""));
    if (qualifies && (!best || r.test.sum_squares_m2 < best->test.sum_squares_m2)) best = &r;
  }

  if (best) {
    const ResidualTest after_train = residual_test(best->train, static_cast<int>(best->result.estimates.size()), sigma_m);
    const ResidualTest after_test = residual_test(best->test, 0, sigma_m);
    const double floor_m = v.budget_m * std::sqrt(8.0 / std::numbers::pi);
    const double train_ratio = best->train.mean_correspondence_m / floor_m;
    const double test_ratio = best->test.mean_correspondence_m / floor_m;
    // Training stages the refit leaves significant (a refit without its residual field, as in
    // unit tests of this rule alone, counts as none).
    int stages = 0, significant_stages = 0;
    if (!best->train_field.stages.empty()) {
      const ResidualAnalysis after = analyse_residuals(best->train_field, sigma_m);
      stages = static_cast<int>(after.stages.size());
      significant_stages = after.significant_stage_count();
    }
    const bool stages_ok = significant_stages <= kMaxSignificantStageFraction * stages;
    const GapTaken train_gap = gap_taken(base_train, best->train, train.significant, floor_m);
    const GapTaken test_gap = gap_taken(base_test, best->test, test.significant, floor_m);
    const bool explained = stages_ok && train_ratio <= kFloorRatio &&
                           (best->test.residual_count == 0 || test_ratio <= kFloorRatio) && train_gap.enough &&
                           test_gap.enough;
    v.reasons.push_back(fmt::format(
        "with {}: mean marker error {:.2f} / {:.2f} x the {}floor (train / held-out; accepted up to {:.2f}); "
        "{} of {} training stages still significant (accepted up to {:.0f} %); gap above the floor taken {} / {} "
        "(train / held-out; needs {:.0f} % where the base is significant); residual RMS {:.2f} / {:.2f} x sigma",
        best->effect, train_ratio, test_ratio, d > 0.0 ? "noise and discretisation " : "noise ", kFloorRatio,
        significant_stages, stages,
        100.0 * kMaxSignificantStageFraction, train_gap.describe(), test_gap.describe(), 100.0 * kMinGapExplained,
        after_train.rms_ratio, after_test.rms_ratio));
    v.chosen = best;
    if (explained) {
      v.verdict = "effect";
      v.effect = best->effect;
      v.summary = fmt::format("missing effect: {} (held-out mean error {:.3f} -> {:.3f} mm)", best->effect,
                              1e3 * base_test.mean_correspondence_m, 1e3 * best->test.mean_correspondence_m);
      return v;
    }
    closest = best;
  }
  // Nothing named. The closest candidate: the refit closest to the held-out data, or without a
  // refit the candidate whose span took the largest share of the residual.
  const CandidateScore* top = nullptr;
  for (const CandidateScore& s : scores) {
    if (s.skipped.empty() && (!top || s.score.explained_fraction > top->score.explained_fraction)) top = &s;
  }
  if (closest) {
    v.closest = closest->effect;
    v.chosen = closest;
  } else if (top) {
    v.closest = top->effect;
  }
  // Is the base fit beyond what noise and discretisation explain, or within it? Only with the
  // discretisation measured: without it a large residual may be the twin's resolution alone.
  const double tolerance = kNoiseTolerance * (1.0 + 2.0 * sigma_relative_error);
  const bool beyond = measured && base_train.rms_m() > kModelFormFactor * v.budget_m;
  const bool within = d > 0.0 && base_train.rms_m() <= tolerance * v.budget_m &&
                      (base_test.residual_count == 0 || base_test.rms_m() <= tolerance * v.budget_m);
  if (beyond) {
    v.verdict = "model_form";
    v.summary = fmt::format("model-form misfit: the base fit leaves {:.3f} mm RMS per coordinate, {:.1f}x what the noise "
                            "and the twin's discretisation explain ({:.3f} mm), and no candidate explains it{}",
                            1e3 * base_train.rms_m(), base_train.rms_m() / v.budget_m, 1e3 * v.budget_m,
                            v.closest ? " (closest: " + *v.closest + ")" : std::string());
    return v;
  }
  if (within) {
    v.verdict = "none";
    v.closest.reset();
    v.chosen = nullptr;
    v.summary = fmt::format("no missing effect supported at this resolution: the base fit's residual (RMS {:.3f} / {:.3f} "
                            "mm, train / held-out) is what the noise ({:.3f} mm) and the twin's discretisation ({:.3f} "
                            "mm) leave; a finer twin resolves smaller effects",
                            1e3 * base_train.rms_m(), 1e3 * base_test.rms_m(), 1e3 * sigma_m, 1e3 * d);
    return v;
  }
  v.verdict = "unexplained";
  if (closest) {
    const CandidateScore* s = score_of(scores, closest->effect);
    v.summary = fmt::format("unexplained: the residual is significant; the closest candidate, {}, explains {:.0f} % of it "
                            "and leaves held-out RMS {:.2f} x sigma",
                            closest->effect, 100.0 * (s ? s->score.explained_fraction : 0.0),
                            residual_test(closest->test, 0, sigma_m).rms_ratio);
  } else {
    v.summary = top ? fmt::format("unexplained: the residual is significant and no candidate's score test is; the "
                                  "closest, {}, explains {:.0f} % of it",
                                  top->effect, 100.0 * top->score.explained_fraction)
                    : "unexplained: the residual is significant and no candidate could be tested";
  }
  return v;
}

}  // namespace twin::diagnosis
