#pragma once
// The process's clock: the wall clock, or simulation time while a SimulatedTime is alive. Every
// reader of time in the cell goes through drivers::host_clock_us() (steady, for ages and pacing)
// and drivers::utime_now() (since the Unix epoch, for message stamps), which ask here, so the
// choice between the wall and the fake world's simulation clock (drivers/sim_clock_client.h) is
// made once per process, as ROS's use_sim_time is. Simulation time is microseconds since the
// Unix epoch (the world's start on the wall plus the simulated time since), so it serves both.
#include <cstdint>

namespace prepreg {

std::int64_t process_steady_us();  // steady clock, or simulation time
std::int64_t process_epoch_us();   // system clock, or simulation time
bool simulated_time_active();

// While one is alive the process runs on the time last set here (0 until set). One at a time per
// process; the destructor returns the process to the wall clock.
class SimulatedTime {
 public:
  SimulatedTime();  // throws std::logic_error when another is alive
  ~SimulatedTime();
  SimulatedTime(const SimulatedTime&) = delete;
  SimulatedTime& operator=(const SimulatedTime&) = delete;
  void set_us(std::int64_t utime);  // never goes back: an older time is ignored
  std::int64_t now_us() const;
};

}  // namespace prepreg
