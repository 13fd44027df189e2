#include "twin/mesh/mesh_io_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace twin::internal {
namespace {

namespace fs = std::filesystem;

// Resolves a 1-based or negative (relative to the end) OBJ index into [0, count).
int obj_index(const fs::path& path, long line, std::string_view token, std::size_t count,
              const char* what) {
  long long i = 0;
  if (!parse_number(token, i) || i == 0) {
    fail_at(path, line,
            std::string("expected a non-zero integer ") + what + " index, got '" +
                std::string(token) + "'");
  }
  const long long n = static_cast<long long>(count);
  const long long resolved = i > 0 ? i - 1 : n + i;
  if (resolved < 0 || resolved >= n) {
    fail_at(path, line,
            std::string(what) + " index " + std::to_string(i) +
                " is out of range: " + std::to_string(n) + " defined so far");
  }
  return static_cast<int>(resolved);
}

}  // namespace

SurfaceMesh read_obj(const fs::path& path, std::string_view text) {
  SurfaceMesh mesh;
  std::vector<Vec2> texcoords;
  std::vector<int> texcoord_of;  // per position: index into texcoords, -1 while unseen
  bool every_corner_has_texcoord = true;
  std::vector<std::array<int, 2>> corners;  // (position, texcoord or -1) of the current face
  LineReader lines(text);
  std::string_view line;
  while (lines.next(line)) {
    const long ln = lines.line();
    const Tokens tok = split(line.substr(0, line.find('#')));
    if (tok.empty()) continue;
    auto numbers = [&](std::size_t count, const char* expected, double* out) {
      if (tok.size() < count + 1) fail_at(path, ln, std::string("expected '") + expected + "'");
      for (std::size_t k = 0; k < count; ++k) {
        if (!parse_number(tok[k + 1], out[k]) || !std::isfinite(out[k])) {
          fail_at(path, ln,
                  std::string("expected a finite number in '") + expected + "', got '" +
                      std::string(tok[k + 1]) + "'");
        }
      }
    };
    if (tok[0] == "v") {
      Vec3 p;
      numbers(3, "v x y z [w]", p.data());
      mesh.positions.push_back(p);
      texcoord_of.push_back(-1);
    } else if (tok[0] == "vt") {
      Vec2 t;
      numbers(2, "vt u v", t.data());
      texcoords.push_back(t);
    } else if (tok[0] == "f") {
      if (tok.size() < 4) fail_at(path, ln, "expected a face with at least 3 vertices");
      corners.clear();
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string_view c = tok[k];
        const std::size_t slash = c.find('/');
        const int p = obj_index(path, ln, c.substr(0, slash), mesh.positions.size(), "vertex");
        int t = -1;
        if (slash != std::string_view::npos) {
          const std::string_view rest = c.substr(slash + 1);
          const std::string_view vt = rest.substr(0, rest.find('/'));
          if (!vt.empty()) t = obj_index(path, ln, vt, texcoords.size(), "texture coordinate");
        }
        if (t < 0) {
          every_corner_has_texcoord = false;
        } else if (texcoord_of[p] < 0) {
          texcoord_of[p] = t;
        } else if (texcoords[texcoord_of[p]] != texcoords[t]) {
          fail_at(
              path, ln,
              "vertex " + std::to_string(p + 1) + " has two different texture coordinates (vt " +
                  std::to_string(texcoord_of[p] + 1) + " and vt " + std::to_string(t + 1) + ")");
        }
        corners.push_back({p, t});
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        mesh.triangles.push_back({corners[0][0], corners[k][0], corners[k + 1][0]});
      }
    }
  }
  const bool all_textured =
      every_corner_has_texcoord && !mesh.triangles.empty() &&
      std::none_of(texcoord_of.begin(), texcoord_of.end(), [](int t) { return t < 0; });
  if (all_textured) {
    for (int t : texcoord_of) mesh.uv.push_back(texcoords[t]);
  }
  return mesh;
}

}  // namespace twin::internal
