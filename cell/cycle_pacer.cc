#include "cell/cycle_pacer.h"

#include <algorithm>
#include <cmath>

namespace cell {

CyclePacer::CyclePacer(double cycle_period_s, double frame_period_s, double frame_slack_s)
    : period_us_(std::llround(1e6 * cycle_period_s)),
      frame_period_us_(frame_period_s > 0 ? std::llround(1e6 * frame_period_s) : 0),
      slack_us_(std::llround(1e6 * frame_slack_s)) {
  if (frame_period_us_ > 0) {
    // Locked only when the cycle period is a whole number of frame periods (within 1 %): else
    // every start would round to a frame and the cycles would not keep the cell's rate.
    const double ratio = cycle_period_s / frame_period_s;
    const double k = std::round(ratio);
    if (k >= 1 && std::abs(ratio - k) <= 0.01 * ratio) frames_per_cycle_ = static_cast<int>(k);
  }
}

std::int64_t CyclePacer::next_start_us(std::int64_t last_start_us, std::int64_t newest_frame_us,
                                       std::int64_t now_us) const {
  const std::int64_t next = frames_per_cycle_ > 0 && newest_frame_us > 0
                                ? newest_frame_us + frames_per_cycle_ * frame_period_us_ + slack_us_
                                : last_start_us + period_us_;
  return std::max(next, now_us);
}

}  // namespace cell
