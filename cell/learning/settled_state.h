#pragma once
// The states of a held sheet worth learning from (issue 35): while the cell runs, the tracked
// surface of cycles in which the grasps stood still and the sheet had stopped moving, averaged
// over a window, with the grasps that held it. A state is what a scanned trial's stage is
// (twin/trials/trial.h), but seen by the cell's own cameras: cell_trial.h writes the states as a
// trial directory, and in_situ_calibration.h fits the material to them.
//
// No LCM, tracker or robot types here: the controller feeds plain vectors, so the same code runs
// on a live cell, on a replayed log and in tests.
#include <cstdint>
#include <optional>
#include <vector>

#include "twin/base/types.h"

namespace cell::learning {

// One settled state: grasps and the tracked sheet averaged over a window of still cycles.
struct SettledObservation {
  std::vector<twin::Vec3> grasp_positions_m;  // per plan grasp: the jaw as measured (cell frame, m)
  std::vector<char> engaged;                  // per plan grasp: still holding
  // Per twin vertex: its mean tracked position over the window (m), NaN for a vertex observed in
  // too few of the window's cycles (SettleOptions::min_observed_fraction).
  std::vector<twin::Vec3> vertices_m;
  // The tracker's scatter (m per coordinate): median over the kept vertices of one cycle's
  // deviation from the window mean (its standard deviation), and that of the mean itself
  // (scatter / sqrt(cycles), cycles taken as independent).
  double cycle_noise_m = 0.0;
  double mean_noise_m = 0.0;
  double coverage = 0.0;  // kept vertices / all vertices
  int cycles = 0;         // tracked cycles averaged
  std::int64_t first_cycle = 0, last_cycle = 0;
  double time_s = 0.0;      // cell time of the window's last cycle (s since the cell started)
  double moved_at_s = 0.0;  // when the grasps last moved or changed before it (s)
  // Median distance (m) between the means of the window's two halves: how still it was.
  double drift_m = 0.0;
  // Fake hardware only: the world's true sheet (SIM_SHEET_TRUTH, its own mesh's vertices, m) as
  // the window ended, so that what the tracker saw can be told from what was there
  // (sim_hw truth_trial). Empty on a real cell.
  std::vector<twin::Vec3> truth_m;
};

struct SettleOptions {
  double window_s = 2.0;             // a state averages this long a window of tracked cycles
  double min_still_s = 3.0;          // the grasps stood still this long before a window starts
  double grasp_tolerance_m = 0.002;  // a grasp moving less than this since the last change is still
  // The sheet is still when the median distance between the half-window means is below this, or
  // below twice what the tracker's scatter alone would make it (a noisy tracker must not keep
  // a state from ever settling).
  double max_drift_m = 0.001;
  double min_observed_fraction = 0.5;  // a vertex seen in fewer of the window's cycles is not kept
  double min_coverage = 0.3;           // a window with fewer kept vertices is no state
};

// Finds settled states in the stream of cycles. Not thread-safe.
class SettledStateDetector {
 public:
  // Throws std::invalid_argument for counts < 1, a cycle rate <= 0 or options out of range.
  SettledStateDetector(int vertex_count, int grasp_count, double cycle_hz, SettleOptions options = {});

  // Every cycle: where the grasps are and which still hold. `tracked_m` / `observed` are the
  // tracked surface (one per twin vertex), empty when the cycle did not track. Returns a state
  // when this cycle completes a settled window; the window then starts anew, so a sheet that
  // stays put gives a state every window_s (the newest is the most settled).
  std::optional<SettledObservation> add_cycle(double time_s, std::int64_t cycle,
                                              const std::vector<twin::Vec3>& grasp_positions_m,
                                              const std::vector<char>& engaged,
                                              const std::vector<twin::Vec3>& tracked_m,
                                              const std::vector<std::uint8_t>& observed);
  // Forgets the window (the tracked surface can no longer be trusted to follow on: the twin was
  // re-seeded, a camera was lost).
  void restart_window() { window_.clear(); }
  int window_cycles() const { return window_cycles_; }

 private:
  struct Frame {
    std::int64_t cycle = 0;
    double time_s = 0.0;
    std::vector<twin::Vec3> tracked_m;
    std::vector<std::uint8_t> observed;
  };
  bool grasps_changed(const std::vector<twin::Vec3>& grasp_positions_m, const std::vector<char>& engaged) const;
  std::optional<SettledObservation> settled() const;

  int vertex_count_, grasp_count_, window_cycles_;
  SettleOptions options_;
  std::vector<twin::Vec3> grasp_reference_m_;
  std::vector<char> engaged_reference_;
  double moved_at_s_ = 0.0;
  bool have_reference_ = false;
  std::vector<Frame> window_;
};

// The states a cell keeps, bounded: a new state of the same grasps as the newest one replaces
// it (the sheet held the same way, seen later: more settled); one of other grasps is appended,
// and beyond max_states the oldest goes. States stay in the order the grasps took them, the
// order a trial's stages must be in.
class SettledStateStore {
 public:
  // Throws std::invalid_argument for max_states < 1 or a negative tolerance.
  explicit SettledStateStore(int max_states = 16, double same_grasp_tolerance_m = 0.005);
  void add(SettledObservation state);
  const std::vector<SettledObservation>& states() const { return states_; }
  // Counts every change (add), so a reader can tell whether anything is new since it looked.
  std::int64_t revision() const { return revision_; }
  // Counts the states appended (not those that replaced the newest): a new way of holding the sheet.
  std::int64_t added() const { return added_; }
  int max_states() const { return max_states_; }

 private:
  bool same_grasps(const SettledObservation& a, const SettledObservation& b) const;
  int max_states_;
  double tolerance_m_;
  std::vector<SettledObservation> states_;
  std::int64_t revision_ = 0, added_ = 0;
};

}  // namespace cell::learning
