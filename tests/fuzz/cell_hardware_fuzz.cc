// The arms-and-grippers part of a cell config (drivers/cell_hardware_config.h).
#include "drivers/cell_hardware_config.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("cell.json", fuzz::as_text(data, size));
  fuzz::read_or_named_error(path, [&] { (void)drivers::read_cell_hardware(path); });
  return 0;
}
