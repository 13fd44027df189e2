// Tracker configuration (tracking/tracker_config_json.h), as the cell and the tracker tools read it.
#include "tests/fuzz/fuzz_support.h"
#include "tracking/tracker_config_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("tracker.json", fuzz::as_text(data, size));
  fuzz::read_or_named_error(path, [&] { (void)tracking::load_tracker_config(path); });
  return 0;
}
