// Trial directories (twin/trials/trial.h: trial.json with its marker, cloud, scan and mesh files),
// as `twin identify`, `twin diagnose` and the lab tools read them, then meshed as identification
// does. The input holds the directory's files (fuzz_support.h: "%%FILE name" lines).
#include "tests/fuzz/fuzz_support.h"
#include "twin/trials/trial.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::read_files_or_named_error(data, size, "trial.json", [](const std::string&) {
    const twin::Trial trial = twin::read_trial(fuzz::scratch_dir().string());
    (void)twin::trial_sheet_mesh(trial, 200);
  });
  return 0;
}
