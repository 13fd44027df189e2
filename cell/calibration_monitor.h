#pragma once
// The running cell's camera calibration check (tracking/calibration_check.h: where two cameras
// see the same part of the sheet, do their clouds agree?), off the cycle's critical path.
//
// The check costs about half a tracker cycle (15-24 ms on the fake cell's scene), so every n-th
// tracked cycle a copy of that cycle's segmented sheet cloud goes to a worker thread and the
// verdict is taken up by a later cycle; a cycle never waits for it. A camera knocked out of
// calibration stays so, and half a second's delay in saying so costs nothing. At start-up the
// check runs at once (check_now): the cell must not reach READY with cameras that disagree.
#include <future>
#include <string>
#include <vector>

#include "cell/background_worker.h"
#include "tracking/calibration_check.h"
#include "tracking/sensor_cloud.h"

namespace cell {

// "" when every judged pair of cameras agrees; else which pair disagrees, by how much, and what
// to check (`cameras` names the cloud's camera indices).
std::string calibration_problem(const std::vector<tracking::CameraPairAgreement>& pairs,
                                const std::vector<std::string>& cameras,
                                const tracking::CalibrationCheckOptions& options);

class CalibrationMonitor {
 public:
  explicit CalibrationMonitor(tracking::CalibrationCheckOptions options) : options_(options) {}

  // Checks the cloud now and keeps the verdict (start-up).
  std::string check_now(const tracking::SensorCloud& cloud, const std::vector<std::string>& cameras);
  // One tracked cycle: takes up a finished check, and every options.every_n_cycles-th call
  // starts one on a copy of `cloud` when none is running. Never waits.
  void after_tracked_cycle(const tracking::SensorCloud& cloud, const std::vector<std::string>& cameras);
  // The newest verdict: "" while the cameras agree (or nothing was judged yet).
  const std::string& problem() const { return problem_; }
  int checks_finished() const { return finished_; }

 private:
  void take_up_finished();

  tracking::CalibrationCheckOptions options_;
  std::string problem_;
  long tracked_cycles_ = 0;
  int finished_ = 0;
  std::future<std::string> running_;
  BackgroundWorker worker_;  // last: finishes a running check before the rest goes
};

}  // namespace cell
