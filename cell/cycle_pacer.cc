#include "cell/cycle_pacer.h"

#include <algorithm>
#include <cmath>

namespace cell {

CyclePacer::CyclePacer(double cycle_period_s, double frame_period_s, double frame_slack_s)
    : period_us_(std::llround(1e6 * cycle_period_s)),
      frame_period_us_(frame_period_s > 0 ? std::llround(1e6 * frame_period_s) : 0),
      slack_us_(std::llround(1e6 * frame_slack_s)) {}

std::int64_t CyclePacer::next_start_us(std::int64_t last_start_us, std::int64_t newest_frame_us,
                                       std::int64_t now_us) const {
  std::int64_t next = last_start_us + period_us_;
  if (frame_period_us_ > 0 && newest_frame_us > 0) {
    // The frame due (plus the slack for its delivery) nearest the nominal start, after the
    // newest one read: at most half a frame period off it. Rounding, not the next frame after
    // it: a cycle that started late (it waited for the last cycle) would otherwise skip a
    // frame that had already arrived. Each start lands on a frame, so the offsets do not add up
    // and the cycles keep the cell's rate.
    const double frames_since = static_cast<double>(next - slack_us_ - newest_frame_us) / frame_period_us_;
    const std::int64_t frames = std::max<std::int64_t>(1, std::llround(frames_since));
    next = newest_frame_us + frames * frame_period_us_ + slack_us_;
  }
  return std::max(next, now_us);
}

}  // namespace cell
