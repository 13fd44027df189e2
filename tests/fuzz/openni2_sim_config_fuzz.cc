// The device list of the OpenNI2 simulation plug-in (sim_hw/openni2_sim_config.h).
#include "sim_hw/openni2_sim_config.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("devices.json", fuzz::as_text(data, size));
  fuzz::read_or_named_error(path, [&] { (void)sim_hw::read_openni2_sim_config(path); });
  return 0;
}
