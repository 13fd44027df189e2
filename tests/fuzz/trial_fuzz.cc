// Trial directories (twin/trials/trial.h: trial.json with its marker, cloud, scan and mesh files),
// as `twin identify`, `twin diagnose` and the lab tools read them, then meshed as identification
// does. The input holds the directory's files (fuzz_support.h: "%%FILE name" lines).
#include "tests/fuzz/fuzz_support.h"
#include "twin/trials/trial.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::write_scratch_files(data, size, "trial.json");
  const std::string dir = fuzz::scratch_dir().string();
  fuzz::read_or_named_error(dir, [&] {
    const twin::Trial trial = twin::read_trial(dir);
    (void)twin::trial_sheet_mesh(trial, 200);
  });
  return 0;
}
