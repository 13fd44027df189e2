#include "twin/mesh/mesh_io_internal.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "twin/mesh/ply_header.h"

namespace twin::internal {
namespace {

namespace fs = std::filesystem;

// Values of an ASCII body: one element per line, errors name the line.
class AsciiSource {
 public:
  AsciiSource(const fs::path& path, std::string_view body, long header_lines)
      : path_(path), lines_(body, header_lines) {}
  void begin(const PlyElement& e, long long index) {
    element_ = &e;
    index_ = index;
    std::string_view line;
    do {
      if (!lines_.next(line)) {
        fail_at(path_, lines_.line() + 1,
                "file ends early: the header declares " + std::to_string(e.count) + " '" + e.name +
                    "' elements, found " + std::to_string(index));
      }
      tokens_ = split(line);
    } while (tokens_.empty());
    next_ = 0;
  }
  double value(PlyType type, const std::string& property) {
    if (next_ >= tokens_.size()) fail("too few values, expected one for '" + property + "'");
    const std::string_view token = tokens_[next_++];
    double v = 0.0;
    long long i = 0;
    const bool ok = is_integer(type) ? parse_number(token, i) : parse_number(token, v);
    if (!ok) {
      fail(std::string("expected ") + (is_integer(type) ? "an integer" : "a number") + " for '" +
           property + "', got '" + std::string(token) + "'");
    }
    return is_integer(type) ? static_cast<double>(i) : v;
  }
  void end() {
    if (next_ != tokens_.size()) fail("more values on the line than the header declares");
  }
  void finish() {
    std::string_view line;
    while (lines_.next(line)) {
      if (!split(line).empty()) {
        fail_at(path_, lines_.line(),
                "data after the last element; the element counts in the header are too small");
      }
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    fail_at(path_, lines_.line(),
            "element " + element_->name + " " + std::to_string(index_) + ": " + what);
  }

 private:
  const fs::path& path_;
  LineReader lines_;
  Tokens tokens_;
  std::size_t next_ = 0;
  const PlyElement* element_ = nullptr;
  long long index_ = 0;
};

// Values of a binary body; errors name the element and its index.
class BinarySource {
 public:
  BinarySource(const fs::path& path, std::string_view body, bool big_endian)
      : path_(path), body_(body), swap_(big_endian != (std::endian::native == std::endian::big)) {}
  void begin(const PlyElement& e, long long index) {
    element_ = &e;
    index_ = index;
  }
  double value(PlyType type, const std::string& property) {
    const std::size_t n = byte_size(type);
    if (body_.size() - pos_ < n) fail("file ends inside property '" + property + "' (truncated)");
    unsigned char b[8];
    std::memcpy(b, body_.data() + pos_, n);
    pos_ += n;
    if (swap_) std::reverse(b, b + n);
    switch (type) {
      case PlyType::kInt8:
        return load<std::int8_t>(b);
      case PlyType::kUint8:
        return load<std::uint8_t>(b);
      case PlyType::kInt16:
        return load<std::int16_t>(b);
      case PlyType::kUint16:
        return load<std::uint16_t>(b);
      case PlyType::kInt32:
        return load<std::int32_t>(b);
      case PlyType::kUint32:
        return load<std::uint32_t>(b);
      case PlyType::kFloat32:
        return load<float>(b);
      case PlyType::kFloat64:
        return load<double>(b);
    }
    return 0.0;
  }
  void end() {}
  void finish() const {
    if (pos_ != body_.size()) {
      throw std::runtime_error(path_.string() + ": " + std::to_string(body_.size() - pos_) +
                               " bytes after the last element; the element counts in the "
                               "header do not match the data");
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path_.string() + ": element " + element_->name + " " +
                             std::to_string(index_) + " of " + std::to_string(element_->count) +
                             ": " + what);
  }

 private:
  template <class T>
  static double load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof(T));
    return static_cast<double>(v);
  }
  const fs::path& path_;
  std::string_view body_;
  bool swap_;
  std::size_t pos_ = 0;
  const PlyElement* element_ = nullptr;
  long long index_ = 0;
};

template <class Source>
SurfaceMesh read_ply_body(Source& src, const PlyHeader& h, const PlyLayout& layout) {
  SurfaceMesh mesh;
  const long long vertex_count = h.elements[layout.vertex].count;
  mesh.positions.resize(vertex_count);
  if (layout.u >= 0) mesh.uv.resize(vertex_count);
  std::vector<long long> polygon;
  for (int e = 0; e < static_cast<int>(h.elements.size()); ++e) {
    const PlyElement& element = h.elements[e];
    for (long long i = 0; i < element.count; ++i) {
      src.begin(element, i);
      for (int k = 0; k < static_cast<int>(element.properties.size()); ++k) {
        const PlyProperty& p = element.properties[k];
        if (!p.is_list) {
          const double value = src.value(p.type, p.name);
          if (e != layout.vertex) continue;
          if (k == layout.x) mesh.positions[i].x() = value;
          if (k == layout.y) mesh.positions[i].y() = value;
          if (k == layout.z) mesh.positions[i].z() = value;
          if (k == layout.u) mesh.uv[i].x() = value;
          if (k == layout.v) mesh.uv[i].y() = value;
          continue;
        }
        const double length = src.value(p.count_type, p.name);
        if (length < 0) src.fail("negative list length for '" + p.name + "'");
        const bool keep = e == layout.face && k == layout.indices;
        polygon.clear();
        for (long long j = 0; j < static_cast<long long>(length); ++j) {
          const double value = src.value(p.type, p.name);
          if (keep) polygon.push_back(static_cast<long long>(value));
        }
        if (!keep) continue;
        if (polygon.size() < 3) {
          src.fail("a face needs at least 3 vertices, got " + std::to_string(polygon.size()));
        }
        for (long long index : polygon) {
          if (index < 0 || index >= vertex_count) {
            src.fail("vertex index " + std::to_string(index) + " is out of range [0, " +
                     std::to_string(vertex_count) + ")");
          }
        }
        for (std::size_t c = 1; c + 1 < polygon.size(); ++c) {
          mesh.triangles.push_back({static_cast<int>(polygon[0]), static_cast<int>(polygon[c]),
                                    static_cast<int>(polygon[c + 1])});
        }
      }
      if (e == layout.vertex &&
          (!mesh.positions[i].allFinite() || (layout.u >= 0 && !mesh.uv[i].allFinite()))) {
        src.fail("coordinate is not finite (NaN or inf)");
      }
      src.end();
    }
  }
  src.finish();
  return mesh;
}

}  // namespace

namespace {

// Counts in a header are not to be trusted before allocating for them: every element of an
// element type with properties takes at least 2 bytes in ASCII ("0\n") and at least the size
// of its scalar properties (and list counts) in binary. A body far too short for the counts is
// rejected here; a slightly short one (a truncated file) fails while reading, naming the element.
void check_counts_fit(const fs::path& path, const PlyHeader& header, std::size_t body_bytes) {
  double least = 0.0;
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty() && element.count > 0) {
      throw std::runtime_error(path.string() + ":" + std::to_string(element.line) + ": element '" +
                               element.name + "' has a count but no properties");
    }
    double bytes = 0.0;
    for (const PlyProperty& p : element.properties) {
      bytes += static_cast<double>(byte_size(p.is_list ? p.count_type : p.type));
    }
    least += static_cast<double>(element.count) * (header.format == PlyFormat::kAscii ? 2.0 : bytes);
  }
  if (least > 2.0 * static_cast<double>(body_bytes) + 1024.0) {
    throw std::runtime_error(path.string() + ": the header declares more elements than the " +
                             std::to_string(body_bytes) + "-byte body can hold (truncated file?)");
  }
}

}  // namespace

SurfaceMesh read_ply(const fs::path& path, std::string_view text) {
  const PlyHeader header = parse_ply_header(path, text);
  const PlyLayout layout = ply_layout(path, header);
  const std::string_view body = text.substr(header.body_offset);
  check_counts_fit(path, header, body.size());
  if (header.format == PlyFormat::kAscii) {
    AsciiSource src(path, body, header.header_lines);
    return read_ply_body(src, header, layout);
  }
  BinarySource src(path, body, header.format == PlyFormat::kBinaryBigEndian);
  return read_ply_body(src, header, layout);
}

}  // namespace twin::internal
