// lcm-logger logs as the log tools read them: diagnose_cell_log (cell/cell_log_cycles.h),
// observed_trial_from_log (cell/log_settled_states.h, with the fake cell's config and plan) and
// cell_monitor --replay (cell/log_replay.h into a monitor). The first byte chooses the tool; the
// rest is the log file (LCM's event log format, read with lcm::LogFile).
#include "cell/cell_config.h"
#include "cell/cell_log_cycles.h"
#include "cell/cell_monitor.h"
#include "cell/log_replay.h"
#include "cell/log_settled_states.h"
#include "tests/fuzz/fuzz_support.h"
#include "twin/trials/grasp_plan.h"

namespace {

struct FakeCell {
  cell::CellConfig config = cell::read_cell_config(PREPREG_SOURCE_DIR "/cell/examples/fake_cell.json");
  twin::GraspPlan plan = twin::read_grasp_plan(config.plan_file);
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static FakeCell fake;
  static drivers::LcmBus bus("memq://");
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("cell.lcmlog", fuzz::as_text(data + 1, size - 1));
  fuzz::read_or_named_error(path, [&] {
    switch (data[0] % 3) {
      case 0: (void)cell::read_logged_cycles(path, 3); break;
      case 1: (void)cell::settled_states_from_log(path, fake.config, fake.plan); break;
      default: {
        std::int64_t clock_utime = 0;
        cell::CellMonitor monitor(bus, cell::MonitorOptions{}, cell::MonitorSinks{},
                                  [&] { return clock_utime; });
        (void)cell::replay_log(path, bus, clock_utime, cell::ReplayOptions{});
        monitor.flush();
      }
    }
  });
  return 0;
}
