#pragma once
// When the cell's next cycle starts. Cycles run at the cell's period; when that period is a
// whole number k of the cameras' frame periods (30 Hz on 30 fps cameras, 10 Hz on 30 fps), each
// start is put just after the frame due k frames after the newest frame the last cycle read: a
// cycle then reads a frame that has just arrived instead of one up to a frame period old, and
// that age is part of the latency from a frame to the error published for it (the fake cell's
// benchmark, 30 Hz cycle and cameras, free-running: frame age at read median 15.6 ms, p99 33.1
// ms; locked: 3.1 and 8.7 ms). Other periods (10 Hz on 15 fps) run free, as before. A cycle that
// ran late starts the next one at once. Times are drivers::host_clock_us() (steady clock, us).
#include <cstdint>

namespace cell {

class CyclePacer {
 public:
  // frame_period_s <= 0: no cameras to follow, the cycles run free at cycle_period_s.
  CyclePacer(double cycle_period_s, double frame_period_s, double frame_slack_s = 0.002);

  // The start of the cycle after one that started at last_start_us and read frames up to
  // newest_frame_us (0: none), given the time now.
  std::int64_t next_start_us(std::int64_t last_start_us, std::int64_t newest_frame_us, std::int64_t now_us) const;
  // Frames per cycle the starts are locked to; 0 when they run free.
  int frames_per_cycle() const { return frames_per_cycle_; }

 private:
  std::int64_t period_us_, frame_period_us_, slack_us_;
  int frames_per_cycle_ = 0;
};

}  // namespace cell
