// cell_monitor's handlers (cell/cell_monitor.h): every channel it subscribes to, messages decoded
// and checked by the bus and handed to the monitor, cycles assembled, compared with the truth and
// printed as cell_monitor prints them. One monitor per input, so each input runs from the same
// start.
#include <memory>

#include "cell/cell_monitor.h"
#include "cell/monitor_format.h"
#include "tests/fuzz/lcm_fuzz_support.h"
#include "tests/fuzz/lcm_harness_channels.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::string> kChannels = fuzz::monitor_channels();
  static drivers::LcmBus bus("memq://");

  std::int64_t clock_us = 1'700'000'000'000'000;
  std::size_t printed = 0;
  cell::MonitorSinks sinks;
  sinks.cycle = [&](const cell::CycleRecord& r) { printed += cell::format_cycle(r).size(); };
  sinks.state_change = [&](const cell::StateChange& c) { printed += cell::format_state_change(c).size(); };
  sinks.calibration = [&](const cell::CalibrationEvent& e) { printed += cell::format_calibration(e).size(); };
  sinks.diagnosis = [&](const cell::DiagnosisEvent& e) { printed += cell::format_diagnosis(e).size(); };
  {
    cell::CellMonitor monitor(bus, cell::MonitorOptions{}, sinks, [&] { return clock_us += 33'333; });
    fuzz::deliver(bus, fuzz::split_messages(data, size, kChannels));
    monitor.flush();
    printed += cell::format_summary(monitor.summary(), bus.counters()).size();
  }
  (void)printed;
  return 0;
}
