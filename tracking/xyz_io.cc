#include "tracking/xyz_io.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "common/durable_file.h"

namespace tracking {
namespace {

// One whitespace-separated field as a double. std::from_chars is used (not strtod or streams)
// because it ignores the global locale, so "0.5" reads the same under a German LC_NUMERIC.
bool parse_number(std::string_view field, double& value) {
  // from_chars rejects a leading '+', which other tools happily write.
  if (field.size() > 1 && field.front() == '+' && field[1] != '-') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  return ec == std::errc() && ptr == end;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

}  // namespace

std::vector<Vec3> parse_xyz(std::istream& in, const std::string& source_name, bool allow_nan) {
  std::vector<Vec3> points;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.empty() || fields.front().front() == '#') continue;
    const auto fail = [&](const std::string& what) {
      throw std::invalid_argument(fmt::format("{}:{}: {}", source_name, line_number, what));
    };
    if (fields.size() != 3) {
      fail(fmt::format("expected 3 numbers \"x y z\" (m), found {} fields", fields.size()));
    }
    Vec3 p;
    int nan_count = 0;
    for (int k = 0; k < 3; ++k) {
      if (!parse_number(fields[k], p(k))) {
        fail(fmt::format("\"{}\" is not a number", fields[k]));
      }
      if (std::isinf(p(k))) fail(fmt::format("\"{}\" is not finite", fields[k]));
      if (std::isnan(p(k))) ++nan_count;
    }
    if (nan_count > 0 && !allow_nan) fail("NaN is not allowed in this file");
    // A point is either known or not: a half-known one is more likely a broken writer.
    if (nan_count > 0 && nan_count < 3) fail("either all three components are nan or none");
    points.push_back(p);
  }
  if (in.bad()) throw std::invalid_argument(source_name + ": read error");
  return points;
}

std::vector<Vec3> read_xyz_file(const std::string& path, bool allow_nan) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open for reading");
  return parse_xyz(in, path, allow_nan);
}

void write_xyz_file(const std::string& path, const std::vector<Vec3>& points,
                    const std::string& header) {
  std::string text;
  if (!header.empty()) {
    std::istringstream lines(header);
    std::string line;
    while (std::getline(lines, line)) text += "# " + line + "\n";
  }
  for (const Vec3& p : points) {
    // fmt's default double format is the shortest text that reads back to the same double, and
    // is locale-independent; NaN prints as "nan".
    if (p.hasNaN()) {
      text += "nan nan nan\n";
    } else {
      text += fmt::format("{} {} {}\n", p.x(), p.y(), p.z());
    }
  }

  prepreg::write_file_atomically(path, text);
}

}  // namespace tracking
