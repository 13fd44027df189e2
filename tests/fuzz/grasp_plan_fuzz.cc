// Grasp plans (twin/trials/grasp_plan.h), as the cell and grasp planning read them.
#include "tests/fuzz/fuzz_support.h"
#include "twin/trials/grasp_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("plan.json", fuzz::as_text(data, size));
  fuzz::read_or_named_error(path, [&] { (void)twin::read_grasp_plan(path); });
  return 0;
}
