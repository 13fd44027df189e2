#include "cell/calibration_monitor.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>

namespace cell {

std::string calibration_problem(const std::vector<tracking::CameraPairAgreement>& pairs,
                                const std::vector<std::string>& cameras,
                                const tracking::CalibrationCheckOptions& options) {
  const auto name = [&](int i) {
    return i >= 0 && i < static_cast<int>(cameras.size()) ? cameras[i] : fmt::format("camera {}", i);
  };
  for (const auto& pair : pairs) {
    if (!pair.flagged) continue;
    return fmt::format("calibration check: cameras {} and {} disagree where both see the sheet "
                       "(median {:.1f} mm, p90 {:.1f} mm; limits {:.1f} / {:.1f} mm): check camera_to_cell",
                       name(pair.camera_a), name(pair.camera_b), 1e3 * pair.median_m, 1e3 * pair.p90_m,
                       1e3 * options.max_median_m, 1e3 * options.max_p90_m);
  }
  return "";
}

std::string CalibrationMonitor::check_now(const tracking::SensorCloud& cloud, const std::vector<std::string>& cameras) {
  problem_ = calibration_problem(
      tracking::check_calibration(cloud, static_cast<int>(cameras.size()), options_), cameras, options_);
  ++finished_;
  return problem_;
}

void CalibrationMonitor::take_up_finished() {
  if (running_.valid() && running_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    record(running_.get());
    ++finished_;
  }
}

bool CalibrationMonitor::wait_for_running_check() const {
  if (!running_.valid()) return false;
  running_.wait();
  return true;
}

void CalibrationMonitor::record(std::string verdict) {
  if (verdict.empty()) {
    disagreeing_in_a_row_ = 0;
    problem_.clear();
  } else if (++disagreeing_in_a_row_ >= kDisagreeingChecksToReport) {
    problem_ = std::move(verdict);
  }
}

double median_vertex_speed_m_s(const std::vector<Eigen::Vector3d>& before_m,
                               const std::vector<Eigen::Vector3d>& after_m, double dt_s) {
  if (before_m.empty() || before_m.size() != after_m.size() || !(dt_s > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  std::vector<double> moves(before_m.size());
  for (std::size_t i = 0; i < moves.size(); ++i) moves[i] = (after_m[i] - before_m[i]).norm();
  auto middle = moves.begin() + moves.size() / 2;
  std::nth_element(moves.begin(), middle, moves.end());
  return *middle / dt_s;
}

void CalibrationMonitor::after_tracked_cycle(const tracking::SensorCloud& cloud,
                                             const std::vector<std::string>& cameras, double sheet_speed_m_s) {
  take_up_finished();
  if (!options_.enabled || !(sheet_speed_m_s <= kStillSheetSpeedMS)) return;
  if (tracked_cycles_++ % std::max(options_.every_n_cycles, 1) != 0) return;
  if (running_.valid()) return;  // the last one is still running: this one is skipped
  auto copy = std::make_shared<const tracking::SensorCloud>(cloud);
  running_ = worker_.submit([copy, cameras, options = options_] {
    omp_set_num_threads(1);  // beside the tracker and the twin: one core's share at most
    return calibration_problem(
        tracking::check_calibration(*copy, static_cast<int>(cameras.size()), options), cameras, options);
  });
}

}  // namespace cell
