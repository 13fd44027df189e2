#pragma once
// Runs the experiment file's states on a READY cell, one call per cycle: apply the state's
// actions (release: the gripper opens and the twin lets go when it reports open; move: the jaw
// target moves in a straight line at the cell's move speed), wait until they are done, let the
// sheet settle for settle_s, then average over the last window_s of cycles:
//   prediction error (tracked vs predicted, observed vertices: what PREDICTION_ERROR carries),
//   the paper's Algorithm 1 figure (observed points to the nearest predicted vertex),
//   and, when SIM_SHEET_TRUTH is on the bus (fake hardware), twin vs truth and tracked vs truth
//   (each true vertex to the twin's / the tracked surface).
// Time counts only while the cell may command (a SAFE_HOLD pauses the experiment).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cell/cell_controller.h"
#include "cell/experiment_file.h"

namespace cell {

struct Averaged {
  int samples = 0;
  double mean_m = 0, max_m = 0;  // averages over the window's cycles of each cycle's mean / max
  void add(double mean, double max);
};

struct StateResult {
  std::string name;
  Averaged prediction, alg1, twin_vs_truth, tracked_vs_truth;
  int cycles = 0;  // cycles in the window
};

class ExperimentRunner {
 public:
  explicit ExperimentRunner(Experiment experiment);

  // After each cycle of `cell`.
  void on_cycle(CellController& cell, const CycleReport& report);
  bool done() const { return index_ >= experiment_.states.size(); }
  const std::vector<StateResult>& results() const { return results_; }
  std::string current() const;  // "state 2/4 'MANUAL released': settling" (for the status line)

 private:
  enum class Phase { kApply, kActing, kSettling, kWindow };
  Experiment experiment_;
  std::size_t index_ = 0;
  Phase phase_ = Phase::kApply;
  double phase_time_s_ = 0;  // wall time in the phase, s
  double last_cycle_s_ = 0;   // steady clock of the previous on_cycle, s
  std::vector<StateResult> results_;
};

// The table printed at the end (mm), one line per state.
std::string format_results(const std::vector<StateResult>& results);
nlohmann::json results_json(const std::vector<StateResult>& results);

}  // namespace cell
