#include "cell/experiment_comparison.h"

#include <fmt/format.h>

#include <cmath>

#include "twin/base/json_field.h"

namespace cell {
namespace {

Averaged read_averaged(const twin::JsonField& state, const char* key) {
  Averaged a;
  const std::optional<twin::JsonField> f = state.optional(key);
  if (!f || f->json().is_null()) return a;  // not measured in that run (no truth on the bus)
  f->only_keys({"mean_m", "max_m", "cycles"});
  a.mean_m = (*f)["mean_m"].non_negative("m");
  a.max_m = (*f)["max_m"].non_negative("m");
  a.samples = (*f)["cycles"].positive_integer();
  return a;
}

std::string pair(const Averaged& a) {
  return a.samples == 0 ? std::string("   -") : fmt::format("{:5.1f}/{:5.1f}", 1e3 * a.mean_m, 1e3 * a.max_m);
}

std::string change(const Averaged& before, const Averaged& after) {
  return fmt::format("{:>11} -> {:<11}", pair(before), pair(after));
}

}  // namespace

std::vector<StateResult> read_results_json(const std::string& path) {
  const nlohmann::json doc = twin::JsonField::parse_file(path);  // outlives the fields that point into it
  const twin::JsonField root(doc, path);
  root.only_keys({"format", "version", "states"});
  if (root["format"].string() != "prepreg_cell_experiment") root["format"].fail("must be \"prepreg_cell_experiment\"");
  std::vector<StateResult> out;
  const twin::JsonField states = root["states"];
  for (std::size_t i = 0; i < states.array_size(); ++i) {
    const twin::JsonField s = states[i];
    s.only_keys({"name", "prediction_error", "algorithm1", "twin_vs_truth", "tracked_vs_truth", "window_cycles"});
    StateResult r;
    r.name = s["name"].string();
    r.prediction = read_averaged(s, "prediction_error");
    r.alg1 = read_averaged(s, "algorithm1");
    r.twin_vs_truth = read_averaged(s, "twin_vs_truth");
    r.tracked_vs_truth = read_averaged(s, "tracked_vs_truth");
    // A whole number that fits an int (1e300 cast to int is undefined behaviour).
    const double cycles = s["window_cycles"].non_negative("");
    if (cycles != std::floor(cycles) || cycles > 1e9) s["window_cycles"].fail("must be a whole number of cycles up to 1e9");
    r.cycles = static_cast<int>(cycles);
    out.push_back(std::move(r));
  }
  return out;
}

std::string format_comparison(const std::vector<StateResult>& before, const std::vector<StateResult>& after) {
  std::string out = fmt::format("{:<24} | {:^26} | {:^26} | {:^26}\n", "state (mean/max mm)",
                                "prediction error", "twin vs truth", "tracked vs truth");
  out += fmt::format("{:<24} | {:^26} | {:^26} | {:^26}\n", "", "before -> after", "before -> after",
                     "before -> after");
  double sums[4] = {0, 0, 0, 0};
  int counts[2] = {0, 0};
  for (const StateResult& b : before) {
    const StateResult* a = nullptr;
    for (const StateResult& x : after) {
      if (x.name == b.name) a = &x;
    }
    const StateResult none;
    const StateResult& aa = a ? *a : none;
    out += fmt::format("{:<24} | {} | {} | {}\n", b.name, change(b.prediction, aa.prediction),
                       change(b.twin_vs_truth, aa.twin_vs_truth), change(b.tracked_vs_truth, aa.tracked_vs_truth));
    if (a && b.prediction.samples > 0 && a->prediction.samples > 0) {
      sums[0] += b.prediction.mean_m;
      sums[1] += a->prediction.mean_m;
      ++counts[0];
    }
    if (a && b.twin_vs_truth.samples > 0 && a->twin_vs_truth.samples > 0) {
      sums[2] += b.twin_vs_truth.mean_m;
      sums[3] += a->twin_vs_truth.mean_m;
      ++counts[1];
    }
  }
  const auto mean = [](double sum, int n) { return n > 0 ? fmt::format("{:5.1f}", 1e3 * sum / n) : std::string("   -"); };
  out += fmt::format("{:<24} | {:>11} -> {:<11} | {:>11} -> {:<11} |\n", "mean over the states", mean(sums[0], counts[0]),
                     mean(sums[1], counts[0]), mean(sums[2], counts[1]), mean(sums[3], counts[1]));
  return out;
}

}  // namespace cell
