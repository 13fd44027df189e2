// When the cell's next cycle starts: at the cycle period, moved onto the cameras' frames.
#include <catch2/catch.hpp>

#include "cell/cycle_pacer.h"

namespace {
constexpr std::int64_t kFrameUs = 33'333;  // 30 fps
}

TEST_CASE("cycle pacer: starts lock just after the next frame, late cycles start at once", "[cell]") {
  const cell::CyclePacer pacer(1.0 / 30.0, 1.0 / 30.0, 0.002);
  const std::int64_t frame = 1'000'000;  // the newest frame the last cycle read arrived here
  // The last cycle started 1 ms after its frame and took 20 ms: the next starts 2 ms after the
  // next frame is due, not a period after the last start (which may fall anywhere between frames).
  CHECK(pacer.next_start_us(frame + 1'000, frame, frame + 21'000) == frame + kFrameUs + 2'000);
  // It started 11 ms after its frame (it had waited for the cycle before): the frame already
  // due by its nominal start is the one taken, not the one after it.
  CHECK(pacer.next_start_us(frame + 11'000, frame, frame + 30'000) == frame + kFrameUs + 2'000);
  // A cycle that took longer than a frame starts the next one at once.
  CHECK(pacer.next_start_us(frame + 1'000, frame, frame + 40'000) == frame + 40'000);
  // No frame read: the plain period.
  CHECK(pacer.next_start_us(frame, 0, frame + 5'000) == frame + kFrameUs);
}

TEST_CASE("cycle pacer: a 10 Hz cell on 30 fps cameras starts every third frame", "[cell]") {
  const cell::CyclePacer pacer(0.1, 1.0 / 30.0, 0.002);
  std::int64_t start = 1'000'000 + 2'000, frame = 1'000'000;
  for (int cycle = 0; cycle < 30; ++cycle) {
    const std::int64_t next = pacer.next_start_us(start, frame, start + 20'000);
    CHECK(next - start == Approx(100'000).margin(1'000));
    frame += 3 * kFrameUs;  // the frame the next cycle reads
    start = next;
    CHECK(start - frame == Approx(2'000).margin(100));  // still just after its frame
  }
}

TEST_CASE("cycle pacer: a cycle period that is no whole number of frames runs free at the cell's rate", "[cell]") {
  // 10 Hz on 15 fps cameras (the fake cell): 1.5 frames a cycle. Locking to frames would round
  // every cycle to one or two frames; it runs at its own period instead.
  const cell::CyclePacer pacer(0.1, 1.0 / 15.0);
  CHECK(pacer.frames_per_cycle() == 0);
  std::int64_t start = 1'000'000, frame = 999'000;
  for (int cycle = 0; cycle < 10; ++cycle) {
    const std::int64_t next = pacer.next_start_us(start, frame, start + 30'000);
    CHECK(next - start == 100'000);
    start = next;
    frame = start - 20'000;
  }
  CHECK(cell::CyclePacer(1.0 / 30.0, 1.0 / 30.0).frames_per_cycle() == 1);
  CHECK(cell::CyclePacer(0.1, 1.0 / 30.0).frames_per_cycle() == 3);
  CHECK(cell::CyclePacer(1.0 / 15.0, 1.0 / 30.0).frames_per_cycle() == 2);
}

TEST_CASE("cycle pacer: without a camera frame period the cycles run free", "[cell]") {
  const cell::CyclePacer pacer(0.05, 0.0);
  CHECK(pacer.next_start_us(1'000'000, 999'000, 1'010'000) == 1'050'000);
  CHECK(pacer.next_start_us(1'000'000, 999'000, 1'060'000) == 1'060'000);
}
