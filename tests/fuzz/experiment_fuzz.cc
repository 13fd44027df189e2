// The cell's experiment files (cell/experiment_file.h) and the results.json that compare_experiments
// reads (cell/experiment_comparison.h). The first byte chooses the reader.
#include "cell/experiment_comparison.h"
#include "cell/experiment_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  fuzz::clear_scratch();
  const bool results = data[0] & 1;
  const std::string path = fuzz::write_scratch_file(results ? "results.json" : "experiment.json",
                                                    fuzz::as_text(data + 1, size - 1));
  fuzz::read_or_named_error(path, [&] {
    if (results) {
      (void)cell::read_results_json(path);
    } else {
      (void)cell::read_experiment(path);
    }
  });
  return 0;
}
