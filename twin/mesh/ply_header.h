#pragma once
// A PLY 1.0 header and where in it the data of a SurfaceMesh sits. Used by the PLY reader
// behind twin/mesh/mesh_io.h; not a public API.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace twin::internal {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

inline std::size_t byte_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

inline bool is_integer(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  // the item type for lists
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  long line = 0;  // header line that declares it
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
  long header_lines = 0;
};

// Which element and property indices hold the data we keep.
struct PlyLayout {
  int vertex = -1, face = -1;
  int x = -1, y = -1, z = -1, u = -1, v = -1, indices = -1;
};

// Parses the header lines up to end_header. Throws std::runtime_error "<path>:<line>: ...".
PlyHeader parse_ply_header(const std::filesystem::path& path, std::string_view text);

// Finds the vertex element's x y z (required) and u v / s t / texture_u texture_v, and the face
// element's vertex_indices or vertex_index list. Throws naming the header line of the element.
PlyLayout ply_layout(const std::filesystem::path& path, const PlyHeader& h);

}  // namespace twin::internal
