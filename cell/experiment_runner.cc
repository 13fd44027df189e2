#include "cell/experiment_runner.h"

#include <fmt/format.h>

#include <cmath>

#include "cell/sheet_compare.h"

namespace cell {

void Averaged::add(double mean, double max) {
  mean_m = (mean_m * samples + mean) / (samples + 1);
  max_m = (max_m * samples + max) / (samples + 1);
  ++samples;
}

ExperimentRunner::ExperimentRunner(Experiment experiment) : experiment_(std::move(experiment)) {}

std::string ExperimentRunner::current() const {
  if (done()) return "experiment done";
  static const char* names[] = {"applying", "acting", "settling", "measuring"};
  return fmt::format("state {}/{} '{}': {}", index_ + 1, experiment_.states.size(),
                     experiment_.states[index_].name, names[static_cast<int>(phase_)]);
}

void ExperimentRunner::on_cycle(CellController& cell, const CycleReport& report) {
  // Wall time: the sheet (real or the fake world's) settles in real time, whatever the cycle
  // rate; time in SAFE_HOLD does not count (the experiment pauses).
  const double now = steady_s();
  const double dt = last_cycle_s_ > 0 ? now - last_cycle_s_ : cell.period_s();
  last_cycle_s_ = now;
  if (done() || !may_command(report.state)) return;
  const ExperimentState& state = experiment_.states[index_];
  switch (phase_) {
    case Phase::kApply:
      for (const auto& a : state.actions) {
        if (a.kind == ExperimentAction::Kind::kRelease) cell.request_release(a.gripper);
        else cell.set_goal(a.gripper, a.to_m);
      }
      phase_ = Phase::kActing;
      phase_time_s_ = 0;
      return;
    case Phase::kActing: {
      bool all = true;
      for (const auto& a : state.actions) {
        all = all && (a.kind == ExperimentAction::Kind::kRelease ? cell.released(a.gripper) : cell.at_goal(a.gripper));
      }
      if (all) {
        phase_ = Phase::kSettling;
        phase_time_s_ = 0;
      }
      return;
    }
    case Phase::kSettling:
      phase_time_s_ += dt;
      if (phase_time_s_ + experiment_.window_s >= state.settle_s) {
        phase_ = Phase::kWindow;
        phase_time_s_ = 0;
        results_.push_back(StateResult{state.name, {}, {}, {}, {}, 0});
      }
      return;
    case Phase::kWindow: {
      StateResult& r = results_.back();
      ++r.cycles;
      if (report.tracked && report.twin_ok) {
        r.prediction.add(report.error.mean_m, report.error.max_m);
        r.alg1.add(report.alg1_mean_m, report.alg1_max_m);
        // The truth is compared only when it is recent (one second): an old one is another state.
        const auto& truth = cell.truth();
        if (!truth.empty() && drivers::host_clock_us() - cell.truth_host_us() < 1'000'000) {
          const tracking::SurfaceMesh twin_mesh = tracking_mesh(cell.twin()->mesh(), cell.prediction());
          const SurfaceGap t = points_to_surface(truth, twin_mesh.vertices_m, twin_mesh.triangles);
          const SurfaceGap o = points_to_surface(truth, cell.last_track().vertices_m, twin_mesh.triangles);
          r.twin_vs_truth.add(t.mean_m, t.max_m);
          r.tracked_vs_truth.add(o.mean_m, o.max_m);
        }
      }
      phase_time_s_ += dt;
      if (phase_time_s_ >= experiment_.window_s) {
        ++index_;
        phase_ = Phase::kApply;
      }
      return;
    }
  }
}

std::string format_results(const std::vector<StateResult>& results) {
  std::string out =
      "state                    | prediction error mean/max mm | Alg.1 mean/max mm | twin vs truth mean/max mm "
      "| tracked vs truth mean/max mm | cycles\n";
  auto pair = [](const Averaged& a) {
    return a.samples == 0 ? std::string("    -   /    -  ") : fmt::format("{:7.2f} / {:7.2f}", 1e3 * a.mean_m, 1e3 * a.max_m);
  };
  for (const auto& r : results) {
    out += fmt::format("{:<24} | {:>28} | {:>17} | {:>25} | {:>28} | {:6d}\n", r.name, pair(r.prediction),
                       pair(r.alg1), pair(r.twin_vs_truth), pair(r.tracked_vs_truth), r.cycles);
  }
  return out;
}

nlohmann::json results_json(const std::vector<StateResult>& results) {
  auto pair = [](const Averaged& a) {
    if (a.samples == 0) return nlohmann::json(nullptr);
    return nlohmann::json{{"mean_m", a.mean_m}, {"max_m", a.max_m}, {"cycles", a.samples}};
  };
  nlohmann::json states = nlohmann::json::array();
  for (const auto& r : results) {
    states.push_back({{"name", r.name},
                      {"prediction_error", pair(r.prediction)},
                      {"algorithm1", pair(r.alg1)},
                      {"twin_vs_truth", pair(r.twin_vs_truth)},
                      {"tracked_vs_truth", pair(r.tracked_vs_truth)},
                      {"window_cycles", r.cycles}});
  }
  return {{"format", "prepreg_cell_experiment"}, {"version", 1}, {"states", states}};
}

}  // namespace cell
