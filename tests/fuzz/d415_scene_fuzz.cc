// Scene files of the simulated D415 (sim_hw/d415_scene_file.h, with the meshes they name), as the
// "simulated" camera back-end reads them. The input holds the files (fuzz_support.h: "%%FILE name"
// lines).
#include "sim_hw/d415_scene_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "scene.json", [](const std::string& path) {
    (void)sim_hw::load_d415_scene_file(path);
  });
  return 0;
}
