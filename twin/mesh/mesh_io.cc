#include "twin/mesh/mesh_io.h"

#include <stdexcept>
#include <string>

#include "twin/mesh/mesh_io_internal.h"

// Only the choice of format by extension lives here; the formats are in obj_reader.cc,
// ply_reader.cc (with ply_header.cc) and mesh_writer.cc.
namespace twin {

namespace fs = std::filesystem;

SurfaceMesh read_surface_mesh(const fs::path& path) {
  const std::string ext = internal::lower_extension(path);
  if (ext != ".obj" && ext != ".ply") {
    throw std::runtime_error(path.string() + ": unknown mesh extension, expected .obj or .ply");
  }
  const std::string text = internal::read_whole_file(path);
  return ext == ".obj" ? internal::read_obj(path, text) : internal::read_ply(path, text);
}

void write_surface_mesh(const fs::path& path, const SurfaceMesh& mesh) {
  const std::string ext = internal::lower_extension(path);
  if (ext == ".ply") return write_ply(path, mesh);
  if (ext == ".obj") return write_obj(path, mesh);
  throw std::invalid_argument(path.string() + ": unknown mesh extension, expected .obj or .ply");
}

}  // namespace twin
