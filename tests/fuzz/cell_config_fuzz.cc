// Cell configs (cell/cell_config.h, with the camera, tracker, material, plan and experiment files
// they name), as cell_controller and the log tools read them at start-up. The input holds the
// files (fuzz_support.h: "%%FILE name" lines).
#include "cell/cell_config.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "cell.json", [](const std::string& path) {
    (void)cell::read_cell_config(path);
  });
  return 0;
}
