// Camera configuration files (drivers/camera_config_json.h), as the cell and camera tools read them.
#include "drivers/camera_config_json.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("cameras.json", fuzz::as_text(data, size));
  fuzz::read_or_named_error(path, [&] { (void)drivers::read_camera_configs(path); });
  return 0;
}
