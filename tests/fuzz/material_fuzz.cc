// Material files (twin/model/material.h), as `twin`, the cell and the lab tools read them.
#include "tests/fuzz/fuzz_support.h"
#include "twin/model/material.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::clear_scratch();
  const std::string path = fuzz::write_scratch_file("material.json", fuzz::as_text(data, size));
  fuzz::read_or_named_error(path, [&] { (void)twin::read_material_file(path); });
  return 0;
}
