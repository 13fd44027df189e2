#pragma once
// The cell controller: start-up (cell_startup.cc), then one cycle per period (cell_cycle.cc):
//   cameras -> tracker (from the twin's newest prediction) -> SHEET_OBSERVED, SHEET_PREDICTED,
//   PREDICTION_ERROR, CAMERA_STATUS_<CAM> -> watchdog -> CELL_STATE -> robot commands (only
//   RUNNING / DEGRADED); beside them, on worker threads, the twin's step with the clamps at the
//   measured grasps (at its own pace unless cell.twin_lockstep) and, every n-th cycle, the
//   cameras' calibration check (calibration_monitor.h).
// The bus is handled on the caller's thread inside startup() and cycle(); nothing here throws
// after construction. With fault_injection the cell obeys SIM_FAULT {target "twin", fault
// "diverge"} by poisoning its twin steps, and {target "twin", fault "slow"} by making each step
// three periods longer, until the fault is cleared; without it SIM_FAULT is ignored (a real
// cell must never act on it).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cell/camera_set.h"
#include "cell/cell_config.h"
#include "cell/cell_messages.h"
#include "cell/background_worker.h"
#include "cell/calibration_monitor.h"
#include "cell/cell_twin.h"
#include "cell/cycle_pacer.h"
#include "cell/learning/branch_following.h"
#include "cell/learning/in_situ_calibration.h"
#include "cell/learning/in_situ_diagnosis.h"
#include "cell/learning/settled_state.h"
#include "cell/robot_link.h"
#include "cell/watchdog.h"
#include "drivers/sim_clock_client.h"
#include "drivers/lcm_bus.h"
#include "tracking/sheet_tracker.h"
#include "twin/trials/grasp_plan.h"

namespace cell {

// What one cycle did, for the status line, the experiment and tests.
struct CycleReport {
  std::int64_t cycle = -1;
  CellState state = CellState::kStarting;
  int frames = 0;
  bool tracked = false;       // the tracker produced a surface
  bool twin_ok = false;       // the twin is healthy: this cycle published its prediction
  bool twin_stepped = false;  // a twin step finished in this cycle and succeeded
  double twin_step_dt_s = 0;  // that step's dt: one period per cycle it spans
  VertexError error;          // tracked vs predicted, observed vertices (published)
  double alg1_mean_m = 0, alg1_max_m = 0;  // the paper's Algorithm 1 (points to predicted vertices)
  double tracker_ms = 0, twin_step_ms = 0, cycle_ms = 0;
  int twin_substeps = 0;      // sub-steps the twin's step needed (1 normally)
  double latency_ms = -1;     // newest frame's arrival -> PREDICTION_ERROR published
  double frame_age_ms = -1;   // newest frame's arrival -> the cycle has its frames (part of latency)
  std::int64_t newest_frame_host_us = 0;  // the newest frame's arrival (host_clock_us), 0: none
  bool commanded = false;     // robot commands were sent this cycle
};

// Seconds on the steady clock (for deadlines).
// The name the cell controller holds the fake world's clock by (cell_world --lockstep).
inline constexpr const char* kLockstepClientName = "cell_controller";

// The process's time in seconds (steady; simulation time on the fake world's clock).
double steady_s();

class CellController {
 public:
  CellController(CellConfig config, drivers::LcmBus& bus, bool fault_injection = false);
  ~CellController();
  CellController(const CellController&) = delete;
  CellController& operator=(const CellController&) = delete;

  // Runs the start-up sequence; returns READY or FAILED (reason() says why). Bounded by
  // cell.startup_timeout_s.
  CellState startup();
  // One cycle; call at cell.cycle_hz (after READY).
  CycleReport cycle();
  // Dispatches waiting LCM messages for up to `ms` of the process's time (between cycles): on
  // the simulation clock ("clock": "sim") it lets the world's clock run `ms` on. 0: only what
  // is waiting.
  void handle_bus(int ms);
  // Handles the bus until the process's time reaches until_us (host_clock_us) or *stop is set.
  void wait_until(std::int64_t until_us, const std::atomic<bool>* stop = nullptr);
  // The fake world's clock when the cell runs on it, else nullptr.
  const drivers::SimClockClient* sim_clock() const { return sim_clock_.get(); }
  // Publishes STOPPED and closes the cameras.
  void stop(const std::string& why);

  CellState state() const { return status_.state; }
  const std::string& reason() const { return status_.reason; }
  const CellConfig& config() const { return config_; }
  double period_s() const { return 1.0 / config_.cell.cycle_hz; }
  // When the next cycle should start (host_clock_us): after `last`, which started at
  // last_start_us, a cycle period on, locked just after a camera frame when the period is a whole
  // number of frame periods (cycle_pacer.h).
  std::int64_t next_cycle_start_us(std::int64_t last_start_us, const CycleReport& last) const;

  // For the experiment: move a gripper's jaw target (straight line at the configured speed) and
  // release a gripper (GRIPPER_COMMAND open once commands are allowed; the twin lets go when
  // the gripper reports not holding, or after release_timeout_s without a status).
  bool set_goal(const std::string& gripper, const twin::Vec3& to_m);
  bool request_release(const std::string& gripper);
  bool at_goal(const std::string& gripper) const;
  bool released(const std::string& gripper) const;  // the twin's clamp has let go

  const twin::GraspPlan& plan() const { return plan_; }
  // The twin itself: its mesh and plan are fixed; its state may be changing on the twin's
  // worker thread, so read the sheet's predicted shape from prediction() instead.
  const CellTwin* twin() const { return twin_.get(); }
  // The twin's newest finished state (3n, cell frame, m), the one the cycle compares and publishes.
  const twin::VecX& prediction() const { return prediction_; }
  const tracking::TrackResult& last_track() const { return last_track_; }
  // SIM_SHEET_TRUTH (fake hardware): the newest true sheet vertices and their host time (us).
  const std::vector<twin::Vec3>& truth() const { return truth_; }
  std::int64_t truth_host_us() const { return truth_host_us_; }
  const RobotLink* robots() const { return robots_.get(); }
  const CameraSet& cameras() const { return cameras_; }
  std::uint64_t dropped_messages() const;  // statuses and faults dropped as malformed
  // Empty when the twin's worker runs at cell.twin_priority; otherwise why it runs at normal.
  std::string twin_priority_problem() { return twin_worker_.priority_problem(); }

  // What the cell learns from its cameras (issue 35, cell_learning.cc; config "learning"): the
  // settled states it keeps, and the calibrations it runs on them in the background.
  // Calibrations write DIR/calibration_<id>/ (trial/, report.md, material.json when adopted)
  // here; without a directory, under the system's temporary directory.
  void set_learning_directory(const std::string& directory) { learning_dir_ = directory; }
  const learning::SettledStateStore& settled_states() const { return settled_states_; }
  // The settled states so far as a trial directory (cell/learning/cell_trial.h), for `twin
  // identify` and `twin diagnose` offline. "" or why not (no state yet, a file not written).
  std::string write_observed_trial(const std::string& directory) const;
  // Tells the calibration and branch workers to stop and waits up to `timeout` for each; true
  // when both are done. A worker that is not is let go (BackgroundWorker::finish_or_let_go): the
  // process should then end with std::_Exit. Also run (with 2 s) by the destructor.
  bool shut_down_background(std::chrono::milliseconds timeout);
  // Blocks until the calibration, diagnosis and branch candidate running in the background (if
  // any) have finished, without taking them up: the next cycle() does, as it would have. True
  // when one was running. For tests and offline tools, which must await a fit by its result:
  // how long it takes depends on the machine and what else runs on it, not on the cell.
  bool wait_for_background_learning();
  // Calibrations finished, and the latest one (nullopt before the first).
  int calibrations() const { return calibrations_; }
  int calibrations_adopted() const { return calibrations_adopted_; }
  const std::optional<learning::CalibrationResult>& last_calibration() const { return last_calibration_; }
  // Diagnoses finished (in_situ_diagnosis.h; after each calibration, or on their own with
  // calibrate off), those whose named effect went into the twin, and the latest one.
  int diagnoses() const { return diagnoses_; }
  int diagnoses_adopted() const { return diagnoses_adopted_; }
  const std::optional<learning::DiagnosisResult>& last_diagnosis() const { return last_diagnosis_; }
  // The material the twin runs (the config's, or the latest adopted calibration once swapped in).
  const twin::Material& material() const { return material_; }
  // Branch following: re-seeds taken, and the latest attempt (nullopt before the first).
  int twin_reseeds() const { return status_.twin_reseeds; }
  int reseed_attempts() const { return reseed_attempts_; }
  // The latest attempt's candidate (its distances, or why none) and whether the twin took it.
  const std::optional<learning::BranchCandidate>& last_reseed() const { return last_reseed_; }
  bool last_reseed_taken() const { return last_reseed_taken_; }
  // Why the latest adopted material could not go into the twin ("" when it did, or none yet).
  const std::string& material_swap_problem() const { return material_swap_problem_; }

 private:
  // cell_startup.cc
  CellState fail(const std::string& why);
  std::string open_cameras(double deadline_s);
  std::string load_job();
  std::string wait_for_robots(double deadline_s);
  std::string first_track(double deadline_s);
  // cell_cycle.cc
  std::vector<twin::Vec3> grasp_positions() const;
  void update_releases(std::int64_t now_us);
  void submit_twin_work();
  void collect_twin_work(CycleReport& report);
  void publish_state();
  void publish_cameras(std::int64_t now_us);
  // cell_learning.cc
  void learn_from_cycle(const CycleReport& report);
  void collect_calibration();
  void start_calibration();
  void start_diagnosis();
  // Where calibrations and diagnoses write: set_learning_directory's, or a per-process folder
  // under the system's temporary directory.
  std::string learning_directory() const;
  void collect_diagnosis();
  void consider_reseed(const learning::SettledObservation& state);
  void collect_branch_job();

  // Between reads while waiting for frames: on the simulation clock time must be let pass
  // for new frames to come (on the wall a read itself waits for one).
  void wait_for_next_frames();
  // Lets the simulation clock run to until_us; notes a clock that fell silent in clock_problem_.
  void advance_clock(std::int64_t until_us, const std::atomic<bool>* stop);

  CellConfig config_;
  CyclePacer pacer_;
  drivers::LcmBus& bus_;
  std::unique_ptr<drivers::SimClockClient> sim_clock_;  // "clock": "sim": made before anything reads time
  std::string clock_problem_;  // "" while the clock runs
  bool fault_injection_;
  CameraSet cameras_;
  tracking::SheetTracker tracker_;  // without its own calibration check: calibration_ runs it
  CalibrationMonitor calibration_;
  twin::GraspPlan plan_;
  twin::Material material_;
  std::unique_ptr<CellTwin> twin_;
  std::unique_ptr<RobotLink> robots_;
  CellStatus status_;
  std::int64_t next_cycle_ = 0;
  std::string twin_problem_;  // "" while the twin is healthy
  twin::VecX prediction_;      // the twin's newest finished state
  std::int64_t prediction_utime_ = 0;  // the time it is for
  std::int64_t twin_cycle_ = 1;        // the cycle the twin's state (or the running step) is for
  tracking::TrackResult last_track_;
  std::vector<twin::Vec3> last_tracked_m_;  // the last tracked surface, for the sheet's speed
  std::int64_t last_tracked_frame_us_ = 0;  // and the arrival of its newest frame
  std::vector<twin::Vec3> truth_;
  std::int64_t truth_host_us_ = 0;
  std::uint64_t faults_dropped_ = 0;
  bool poison_requested_ = false;  // SIM_FAULT twin diverge active (kept across re-creation)
  std::chrono::milliseconds stall_requested_{0};  // SIM_FAULT twin slow: the stall it asks for
  struct Release {
    int grasp = -1, gripper = -1;
    bool commanded = false;
    std::int64_t commanded_host_us = 0;
    bool done = false;
  };
  std::vector<Release> releases_;
  std::vector<drivers::LcmBus::SubscriptionId> subscriptions_;
  // What the twin did on its worker: a step or, after a failure, a fresh static equilibrium, or
  // the equilibrium under a newly adopted material (swapped).
  struct TwinWork {
    bool stepped = false;
    TwinStepResult step;
    double dt_s = 0;
    std::string initialise_problem;  // of the re-initialisation, empty when it worked
    bool swapped = false;            // the job took up pending_material_
    bool reseeded = false;           // the job took up pending_state_ (branch following)
    std::int64_t state_utime = 0;    // the time its state is for
  };
  std::future<TwinWork> twin_work_;  // valid while the twin's worker has a job of ours
  // Learning (cell_learning.cc).
  double started_s_ = steady_s();
  std::unique_ptr<learning::SettledStateDetector> settled_detector_;
  learning::SettledStateStore settled_states_;
  std::int64_t calibrated_at_added_ = 0;  // settled_states_.added() when the last calibration started
  std::string learning_dir_;
  std::optional<twin::Material> pending_material_;  // adopted, not yet in the twin
  // Branch following (cell_learning.cc): a candidate equilibrium near the settled sheet, found on
  // branch_worker_, and the state the twin's worker is to continue from.
  struct BranchJob {
    learning::BranchCandidate candidate;
    std::int64_t added = 0;                      // settled_states_.added() when it started
    std::vector<twin::Vec3> grasp_positions_m;  // the state's grasps
    std::vector<char> engaged;
  };
  std::future<BranchJob> branch_job_;
  std::optional<twin::VecX> pending_state_;
  std::int64_t reseed_tried_at_added_ = 0;  // settled_states_.added() at the last attempt
  std::optional<learning::BranchCandidate> last_reseed_;  // without its x
  bool last_reseed_taken_ = false;
  int reseed_attempts_ = 0;
  std::string material_swap_problem_;  // why the last adopted material did not go in ("" if it did)
  int calibrations_ = 0, calibrations_adopted_ = 0;
  std::optional<learning::CalibrationResult> last_calibration_;
  struct CalibrationJob {
    std::int64_t id = 0;
    learning::CalibrationResult result;
    std::string directory, material_file;
  };
  std::future<CalibrationJob> calibration_job_;
  // Diagnoses run on calibration_worker_ after the calibration of the same states.
  int diagnoses_ = 0, diagnoses_adopted_ = 0;
  std::optional<learning::DiagnosisResult> last_diagnosis_;
  struct DiagnosisJob {
    std::int64_t id = 0;
    learning::DiagnosisResult result;
  };
  std::future<DiagnosisJob> diagnosis_job_;
  std::int64_t diagnosed_at_added_ = 0;  // settled_states_.added() when the last diagnosis started
  std::shared_ptr<std::atomic<bool>> calibration_cancelled_ = std::make_shared<std::atomic<bool>>(false);
  // Run calibrations and branch candidates, by default at idle priority: only on CPU the cycle and
  // the twin leave (two workers: a candidate is seconds, a calibration minutes).
  BackgroundWorker calibration_worker_;  // at config learning.priority (idle by default)
  BackgroundWorker branch_worker_;
  // Runs the twin's step beside the tracker (cell_cycle.cc). Declared last, so it is destroyed
  // (finishing any step it runs) before the twin is.
  BackgroundWorker twin_worker_;
};

}  // namespace cell
