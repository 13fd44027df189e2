// The fake world's config (sim_hw/world_config.h: world.json with the cell config, plan, material
// and scene files it uses), as fake_world reads it. The input holds the files (fuzz_support.h:
// "%%FILE name" lines); world.json comes first.
#include "sim_hw/world_config.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "world.json", [](const std::string& world) {
    (void)sim_hw::read_world_config((fuzz::scratch_dir() / "cell.json").string(), world);
  });
  return 0;
}
