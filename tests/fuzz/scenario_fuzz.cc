// Scenario files (twin/trials/scenario.h, with the material file they may name), as `twin
// simulate` reads them. The input holds the files (fuzz_support.h: "%%FILE name" lines).
#include "tests/fuzz/fuzz_support.h"
#include "twin/trials/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "scenario.json", [](const std::string& path) {
    (void)twin::read_scenario_file(path);
  });
  return 0;
}
