#include "twin/diagnosis/diagnosis_output.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "twin/base/atomic_file.h"
#include "twin/diagnosis/diagnosis_report.h"

namespace twin::diagnosis {
namespace {

nlohmann::json estimates_json(const std::vector<ParameterEstimate>& estimates) {
  nlohmann::json p = nlohmann::json::object();
  for (const ParameterEstimate& e : estimates) {
    p[std::string(parameter_name(e.parameter))] = {
        {"value", e.value}, {"lower95", e.lower95}, {"upper95", e.upper95}, {"determined", e.determined},
        {"at_search_edge", e.at_search_edge}};
  }
  return p;
}

nlohmann::json before_after(const SetScore& before, const std::optional<SetScore>& after, bool effect) {
  const double b = 1e3 * before.mean_correspondence_m;
  return {{"before_mean_mm", b}, {"after_mean_mm", effect && after ? 1e3 * after->mean_correspondence_m : b}};
}

std::string fixed(double v, int digits) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "-"; }
std::string general(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "-"; }

const Refit* refit_of(const DiagnosisRecord& r, const std::string& effect) {
  for (const Refit& f : r.refits) {
    if (f.effect == effect) return &f;
  }
  return nullptr;
}

ResidualAnalysis analyse(const ResidualField& field, double sigma_m) { return analyse_residuals(field, sigma_m); }

// Where a profiled candidate's score was taken, e.g. "scored at clamp_grip_width_m = 0.03 (largest of 4)".
std::string profile_note(const CandidateScore& s) {
  if (!s.profile) return "";
  return fmt::format("scored at {} = {:.4g} (largest of {})", parameter_name(s.profile->parameter), s.profile->value,
                     s.profile->values_tried);
}

// The robust pass of a refit (Refit::RobustPass), or null when no stage was an outlier.
nlohmann::json robust_json(const std::optional<Refit::RobustPass>& pass) {
  if (!pass) return nullptr;
  nlohmann::json stages = nlohmann::json::array();
  for (const OutlierStage& o : pass->outliers) {
    stages.push_back({{"trial", o.trial}, {"stage", o.stage}, {"rms_mm", 1e3 * o.rms_m}, {"ratio_to_median", o.ratio},
                      {"weight", o.weight}});
  }
  const auto rms_mm = [](double m2) { return std::isfinite(m2) ? nlohmann::json(1e3 * std::sqrt(m2)) : nlohmann::json(nullptr); };
  return {{"outlier_stages", stages},
          {"least_squares_rms_mm", rms_mm(pass->least_squares_m2)},
          {"robust_rms_mm", rms_mm(pass->robust_m2)},
          {"kept", pass->kept}};
}

// One report line on a refit's robust pass.
std::string robust_note(const Refit& r) {
  std::string stages;
  for (const OutlierStage& o : r.robust->outliers) {
    stages += fmt::format("{}{}/{} ({:.1f}x)", stages.empty() ? "" : ", ", o.trial, o.stage, o.ratio);
  }
  const std::string outcome =
      std::isfinite(r.robust->robust_m2)
          ? fmt::format("fresh training RMS {:.3f} mm against least squares' {:.3f} mm: {}", 1e3 * std::sqrt(r.robust->robust_m2),
                        1e3 * std::sqrt(r.robust->least_squares_m2), r.robust->kept ? "kept" : "not kept")
          : std::string("it gave no result");
  return fmt::format("refit {}: training stage(s) {} far above the median stage misfit; refitted with them "
                     "down-weighted, then without weights: {}",
                     r.effect, stages, outcome);
}

}  // namespace

nlohmann::json verdict_json(const DiagnoseOutcome& o, const DiagnosisRecord& record) {
  const Verdict& v = o.verdict;
  const bool effect = v.verdict == "effect";
  nlohmann::json j;
  j["verdict"] = v.verdict;
  j["effect"] = effect ? nlohmann::json(*v.effect) : nlohmann::json(nullptr);
  j["closest"] = v.closest ? nlohmann::json(*v.closest) : nlohmann::json(nullptr);
  j["summary"] = v.summary;
  // The named effect's refit (every fitted parameter); otherwise the base fit's.
  j["parameters"] = estimates_json(effect ? o.parameters : record.base.estimates);
  j["noise_floor_mm"] = 1e3 * o.noise_floor_m;
  j["noise_sigma_mm"] = 1e3 * o.sigma_m;
  j["noise_estimated"] = o.sigma_estimated;
  j["noise_estimated_on"] = o.sigma_estimated ? nlohmann::json(o.sigma_source) : nlohmann::json(nullptr);
  j["discretisation_mm"] = o.discretisation.usable() && o.discretisation.triangles > 0
                               ? nlohmann::json(1e3 * o.discretisation.rms_m)
                               : nlohmann::json(nullptr);
  const bool measured = o.discretisation.usable() && o.discretisation.triangles > 0;
  j["discretisation_in_residual_mm"] = measured ? nlohmann::json(1e3 * o.discretisation.error_in_residual_rms_m)
                                                : nlohmann::json(nullptr);
  j["model_form_misfit"] = o.model_form_misfit;
  j["budget_mm"] = 1e3 * v.budget_m;  // sqrt(sigma^2 + d^2): what noise and discretisation explain
  j["model_form"] = nullptr;
  if (o.model_form) {
    nlohmann::json where{{"threshold_mm", 1e3 * o.model_form->threshold_m},
                         {"stages", nlohmann::json::array()},
                         {"regions", nlohmann::json::array()}};
    for (const MisfitStage& st : o.model_form->stages)
      where["stages"].push_back({{"stage", st.label}, {"rms_mm", 1e3 * st.rms_m}, {"markers", st.samples}});
    for (const MisfitRegion& r : o.model_form->regions) {
      where["regions"].push_back({{"trial", r.trial},
                                  {"row", r.row},
                                  {"col", r.col},
                                  {"u_m", {r.min_uv_m.x(), r.max_uv_m.x()}},
                                  {"v_m", {r.min_uv_m.y(), r.max_uv_m.y()}},
                                  {"rms_mm", 1e3 * r.rms_m},
                                  {"samples", r.samples}});
    }
    j["model_form"] = where;
  }
  j["held_out"] = before_after(o.base_test, o.after_test, effect);
  j["train"] = before_after(o.base_train, o.after_train, effect);
  j["base_branch_of"] = record.base_branch_of ? nlohmann::json(*record.base_branch_of) : nlohmann::json(nullptr);
  j["optimizer"] = record.optimizer;
  j["evidence"] = v.reasons;
  j["candidates"] = nlohmann::json::array();
  auto candidate = [&](const CandidateScore& s) {
    nlohmann::json c{{"effect", s.effect},
                     {"score_statistic", s.score.statistic},
                     {"dof", s.score.dof},
                     {"p_value", s.score.p_value},
                     {"explained_fraction", s.score.explained_fraction},
                     // RMS per coordinate it could take of the twin's discretisation error (mm)
                     {"absorbable_discretisation_mm",
                      s.score.absorbable_m2 >= 0.0 && o.base_train.residual_count > 0
                          ? nlohmann::json(1e3 * std::sqrt(s.score.absorbable_m2 / o.base_train.residual_count))
                          : nlohmann::json(nullptr)},
                     {"skipped", s.skipped.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.skipped)},
                     {"profile", nullptr},
                     {"refit", nullptr}};
    if (s.profile) {
      c["profile"] = {{"parameter", parameter_name(s.profile->parameter)},
                      {"value", s.profile->value},
                      {"values_tried", s.profile->values_tried}};
    }
    if (const Refit* r = refit_of(record, s.effect)) {
      c["refit"] = r->usable() ? nlohmann::json{{"parameters", estimates_json(r->result.estimates)},
                                                {"bic", r->information_criterion},
                                                {"bic_base", record.base_bic},
                                                {"train_mean_mm", 1e3 * r->train.mean_correspondence_m},
                                                {"held_out_mean_mm", 1e3 * r->test.mean_correspondence_m},
                                                {"held_out_rms_mm", 1e3 * r->test.rms_m()},
                                                {"robust", robust_json(r->robust)}}
                               : nlohmann::json{{"failure", r->failure}};
    }
    j["candidates"].push_back(c);
  };
  for (int i : record.ranking) candidate(record.scores[i]);
  for (const CandidateScore& s : record.scores) {
    if (!s.skipped.empty()) candidate(s);
  }
  return j;
}

std::string write_diagnosis_files(const DiagnoseOptions& options, const DiagnoseOutcome& o,
                                  const DiagnosisRecord& record, const std::vector<CandidateEffect>& candidates) {
  const std::filesystem::path dir(options.report);
  create_directories_durably(dir);
  const Verdict& v = o.verdict;
  const bool effect = v.verdict == "effect";
  const std::filesystem::path augmented = dir / "material_augmented.json";
  if (effect) {
    Material m = v.chosen->result.material;
    m.name = record.base.material.name + " + " + *v.effect;
    write_material_file(augmented.string(), m);
  } else {
    std::filesystem::remove(augmented);  // a stale one from an earlier run would mislead
  }
  write_file_atomically(dir / "verdict.json",
                        [&](std::ostream& out) { out << verdict_json(o, record).dump(2) << "\n"; });

  ReportData data;
  data.verdict_line = v.summary;  // begins with what the verdict is
  data.noise_floor_m = o.sigma_m;
  data.noise_source = o.sigma_estimated ? o.sigma_source : "";
  data.parameters.header = {"parameter", "value", "lower 95 %", "upper 95 %", "determined"};
  for (const ParameterEstimate& e : effect ? o.parameters : record.base.estimates) {
    data.parameters.rows.push_back({std::string(parameter_name(e.parameter)), general(e.value), general(e.lower95),
                                    general(e.upper95), e.determined ? "yes" : e.at_search_edge ? "no (search range's edge)" : "no"});
  }
  data.candidates.header = {"candidate", "score", "dof", "p", "explained %", "refit held-out mm", "BIC - base", "note"};
  auto row = [&](const CandidateScore& s) {
    const Refit* r = refit_of(record, s.effect);
    const bool fitted = r && r->usable();
    data.candidates.rows.push_back({s.effect, fixed(s.score.statistic, 1), std::to_string(s.score.dof),
                                    general(s.score.p_value), fixed(100 * s.score.explained_fraction, 1),
                                    fitted ? fixed(1e3 * r->test.mean_correspondence_m, 3) : "-",
                                    fitted ? fixed(r->information_criterion - record.base_bic, 1) : "-",
                                    s.skipped.empty() ? (r && !r->usable() ? r->failure : profile_note(s)) : s.skipped});
  };
  for (int i : record.ranking) row(record.scores[i]);
  for (const CandidateScore& s : record.scores) {
    if (!s.skipped.empty()) row(s);
  }
  data.notes = v.reasons;
  data.notes.push_back(fmt::format("noise sigma {:.3f} mm per coordinate ({}); noise floor of the mean "
                                   "correspondence error {:.3f} mm",
                                   1e3 * o.sigma_m, o.sigma_estimated ? "estimated on " + o.sigma_source : std::string("given"),
                                   1e3 * o.noise_floor_m));
  if (o.discretisation.triangles > 0) data.notes.push_back("twin's discretisation: " + describe(o.discretisation, "at the base fit"));
  data.notes.push_back(fmt::format("candidates considered: {}; base fit {} ({} evaluations)", candidates.size(),
                                   record.base.stop_reason, record.base.evaluations));
  for (const Refit& r : record.refits) {
    if (r.robust) data.notes.push_back(robust_note(r));
  }
  if (v.chosen) data.after_label = "with " + v.chosen->effect;
  auto phase = [&](const std::string& name, const ResidualField& before, const ResidualField* after) {
    ReportPhase p;
    p.name = name;
    p.before = before;
    p.before_analysis = analyse(before, o.sigma_m);
    if (after) {
      p.after = *after;
      p.after_analysis = analyse(*after, o.sigma_m);
    }
    data.phases.push_back(std::move(p));
  };
  phase("train", record.train_before, v.chosen ? &v.chosen->train_field : nullptr);
  phase("held-out", record.test_before, v.chosen ? &v.chosen->test_field : nullptr);
  write_report(data, dir);
  return terminal_summary(data);
}

}  // namespace twin::diagnosis
