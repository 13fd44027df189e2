// Point files ("x y z" per line): the twin's reader (trial markers and clouds, twin/trials/trial.h)
// and the tracker's (scans and guides, tracking/xyz_io.h). The first byte chooses the reader and
// whether "nan nan nan" (a marker not seen) is allowed.
#include "tests/fuzz/fuzz_support.h"
#include "tracking/xyz_io.h"
#include "twin/trials/trial.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  fuzz::clear_scratch();
  const bool allow_nan = data[0] & 1;
  const bool tracker = data[0] & 2;
  const std::string path = fuzz::write_scratch_file("points.xyz", fuzz::as_text(data + 1, size - 1));
  fuzz::read_or_named_error(path, [&] {
    if (tracker) {
      (void)tracking::read_xyz_file(path, allow_nan);
    } else {
      (void)twin::read_xyz_file(path, allow_nan);
    }
  });
  return 0;
}
