// Plain-text point files ("x y z" per line); see trial.h.

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/base/atomic_file.h"
#include "twin/mesh/mesh_io_internal.h"
#include "twin/trials/trial.h"

namespace twin {
namespace {

// One non-comment line of an xyz file: three finite numbers, or (markers only) three NaNs.
Vec3 parse_xyz_line(const std::string& path, long line, const internal::Tokens& tokens,
                    bool allow_nan) {
  const char* expected = allow_nan ? "\"x y z\" (m) or \"nan nan nan\"" : "\"x y z\" (m)";
  if (tokens.size() != 3) {
    internal::fail_at(path, line, fmt::format("expected 3 values {}, got {}", expected, tokens.size()));
  }
  Vec3 p;
  int nan_count = 0;
  for (int k = 0; k < 3; ++k) {
    const std::string token(tokens[k]);
    if (!internal::parse_number(tokens[k], p[k])) {
      internal::fail_at(path, line, fmt::format("expected a number in {}, got '{}'", expected, token));
    }
    if (std::isinf(p[k])) {
      internal::fail_at(path, line, "expected a finite number, got '" + token + "'");
    }
    if (std::isnan(p[k])) {
      if (!allow_nan) {
        internal::fail_at(path, line, "expected a finite number, got '" + token +
                                          "' (NaN is only for markers not seen)");
      }
      ++nan_count;
    }
  }
  if (nan_count != 0 && nan_count != 3) {
    internal::fail_at(path, line, "a marker not seen is \"nan nan nan\"; a partly NaN position is not allowed");
  }
  if (nan_count == 3) p.setConstant(std::numeric_limits<double>::quiet_NaN());
  return p;
}

}  // namespace

std::vector<Vec3> read_xyz_file(const std::string& path, bool allow_nan) {
  const std::string text = internal::read_whole_file(path);
  internal::LineReader lines(text);
  std::string_view line;
  std::vector<Vec3> points;
  while (lines.next(line)) {
    const internal::Tokens tokens = internal::split(line);
    if (tokens.empty() || tokens.front().front() == '#') continue;
    points.push_back(parse_xyz_line(path, lines.line(), tokens, allow_nan));
  }
  return points;
}

void write_xyz_file(const std::string& path, const std::vector<Vec3>& points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    // Anything else would be written but not read back.
    if (points[i].hasNaN() ? !points[i].array().isNaN().all() : !points[i].allFinite()) {
      throw std::invalid_argument(fmt::format("{}: point {} is ({}, {}, {}): expected finite "
                                              "coordinates, or all three NaN for a marker not seen",
                                              path, i, points[i].x(), points[i].y(), points[i].z()));
    }
  }
  write_file_atomically(path, [&](std::ostream& out) {
    for (const Vec3& p : points) {
      if (p.hasNaN()) {
        out << "nan nan nan\n";  // spelt out: a stream may print "-nan" for a NaN with its sign bit set
      } else {
        out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      }
    }
  });
}

}  // namespace twin
