#include "twin/mesh/mesh_io.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <stdexcept>
#include <string>

#include "twin/base/atomic_file.h"

namespace twin {
namespace {

namespace fs = std::filesystem;

void check_for_writing(const fs::path& path, const SurfaceMesh& mesh,
                       const std::vector<VertexScalar>& scalars) {
  const std::size_t n = mesh.positions.size();
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument(path.string() + ": cannot write mesh: " + what);
  };
  if (!mesh.uv.empty() && mesh.uv.size() != n) {
    bad("uv has " + std::to_string(mesh.uv.size()) + " entries for " + std::to_string(n) +
        " vertices");
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int i : mesh.triangles[t]) {
      if (i < 0 || static_cast<std::size_t>(i) >= n) {
        bad("triangle " + std::to_string(t) + " refers to vertex " + std::to_string(i));
      }
    }
  }
  std::vector<std::string> names = {"x", "y", "z", "u", "v"};
  for (const VertexScalar& s : scalars) {
    if (s.values.size() != n) {
      bad("scalar '" + s.name + "' has " + std::to_string(s.values.size()) + " values for " +
          std::to_string(n) + " vertices");
    }
    const bool blank = std::any_of(s.name.begin(), s.name.end(), [](char c) {
      return std::isspace(static_cast<unsigned char>(c));
    });
    if (s.name.empty() || blank || std::count(names.begin(), names.end(), s.name) > 0) {
      bad("scalar name '" + s.name + "' is empty, has whitespace or is already used");
    }
    names.push_back(s.name);
  }
}

template <class T>
void put_little_endian(std::ostream& out, T value) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + sizeof(T));
  out.write(b, sizeof(T));
}

}  // namespace

void write_ply(const fs::path& path, const SurfaceMesh& mesh,
               const std::vector<VertexScalar>& scalars, bool binary) {
  check_for_writing(path, mesh, scalars);
  const bool has_uv = !mesh.uv.empty();
  write_file_atomically(path, [&](std::ostream& out) {
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
        << "element vertex " << mesh.positions.size() << "\n"
        << "property double x\nproperty double y\nproperty double z\n";
    if (has_uv) out << "property double u\nproperty double v\n";
    for (const VertexScalar& s : scalars) out << "property double " << s.name << "\n";
    out << "element face " << mesh.triangles.size() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      std::vector<double> row(mesh.positions[i].data(), mesh.positions[i].data() + 3);
      if (has_uv) row.insert(row.end(), {mesh.uv[i].x(), mesh.uv[i].y()});
      for (const VertexScalar& s : scalars) row.push_back(s.values[i]);
      for (std::size_t k = 0; k < row.size(); ++k) {
        if (binary)
          put_little_endian(out, row[k]);
        else
          out << row[k] << (k + 1 < row.size() ? ' ' : '\n');
      }
    }
    for (const auto& tri : mesh.triangles) {
      if (binary) {
        put_little_endian<std::uint8_t>(out, 3);
        for (int i : tri) put_little_endian<std::int32_t>(out, i);
      } else {
        out << "3 " << tri[0] << ' ' << tri[1] << ' ' << tri[2] << '\n';
      }
    }
  });
}

void write_obj(const fs::path& path, const SurfaceMesh& mesh) {
  check_for_writing(path, mesh, {});
  write_file_atomically(path, [&](std::ostream& out) {
    for (const Vec3& p : mesh.positions)
      out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const Vec2& t : mesh.uv) out << "vt " << t.x() << ' ' << t.y() << '\n';
    for (const auto& tri : mesh.triangles) {
      out << 'f';
      for (int i : tri) {
        out << ' ' << i + 1;
        if (!mesh.uv.empty()) out << '/' << i + 1;
      }
      out << '\n';
    }
  });
}

}  // namespace twin
