// OBJ and PLY meshes (twin/mesh/mesh_io.h: ascii and binary PLY), as trials, scenarios, goals and
// the simulated cameras read them, then made into a sheet as a trial's mesh_file is. The first
// byte chooses the extension.
#include "tests/fuzz/fuzz_support.h"
#include "twin/mesh/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  fuzz::clear_scratch();
  static const char* const kNames[] = {"mesh.obj", "mesh.ply", "MESH.PLY", "mesh.OBJ"};
  const std::string path = fuzz::write_scratch_file(kNames[data[0] % 4], fuzz::as_text(data + 1, size - 1));
  fuzz::read_or_named_error(path, [&] {
    const twin::SurfaceMesh mesh = twin::read_surface_mesh(path);
    // A flat mesh becomes a sheet (its own errors name no file: the caller adds that).
    try {
      (void)twin::sheet_mesh_from_flat(mesh);
    } catch (const std::invalid_argument&) {
    }
  });
  return 0;
}
