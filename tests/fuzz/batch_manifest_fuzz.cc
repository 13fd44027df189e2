// Batch manifests (twin/batch/batch_manifest.h) as `twin batch` reads them, with the trial
// directories and start material they name, then what a rerun reads back from each material's
// directory (twin/batch/batch_resume.h): NAME/done.json and NAME/running.json. The input holds
// the files (fuzz_support.h: "%%FILE name" lines); a directory exists when a file is given in it.
// A done.json is read back only when it records the material's manifest entry, whose fingerprint
// holds the scratch directory's absolute paths that no input can know: here every material's
// fingerprint is "fuzz", so that inputs reach the reading of the row.
#include <filesystem>

#include "tests/fuzz/fuzz_support.h"
#include "twin/batch/batch_manifest.h"
#include "twin/batch/batch_resume.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "manifest.json", [](const std::string& path) {
    const twin::batch::BatchManifest manifest = twin::batch::read_batch_manifest(path);
    for (twin::batch::BatchMaterial material : manifest.materials) {
      material.fingerprint = "fuzz";
      const std::filesystem::path dir = fuzz::scratch_dir() / material.name;
      (void)twin::batch::interrupted_run(dir);
      (void)twin::batch::finished_row(dir, material);
    }
  });
  return 0;
}
