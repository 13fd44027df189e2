#include "twin/mesh_io.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace twin {
namespace {

namespace fs = std::filesystem;
using Tokens = std::vector<std::string_view>;

[[noreturn]] void fail_at(const fs::path& path, long line, const std::string& what) {
  throw std::runtime_error(path.string() + ":" + std::to_string(line) + ": " + what);
}

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string short_number(double value) {
  std::ostringstream out;
  out << std::setprecision(4) << value;
  return out.str();
}

std::string read_whole_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error(path.string() + ": cannot open for reading");
  std::string data(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  if (!in.read(data.data(), static_cast<std::streamsize>(data.size()))) {
    throw std::runtime_error(path.string() + ": read failed");
  }
  return data;
}

Tokens split(std::string_view line) {
  Tokens tokens;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i == line.size()) return tokens;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    tokens.push_back(line.substr(start, i - start));
  }
}

// from_chars rejects a leading '+', which C's strtod (and so many writers' readers) accept.
template <class T>
bool parse_number(std::string_view s, T& out) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end;
}

// Lines of a text (LF or CRLF), numbered from 1 + the number of lines already consumed.
class LineReader {
 public:
  explicit LineReader(std::string_view text, long lines_before = 0)
      : text_(text), line_(lines_before) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = std::min(end + 1, text_.size());
    ++line_;
    return true;
  }
  long line() const { return line_; }          // number of the line last returned
  std::size_t offset() const { return pos_; }  // byte offset just after it

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  long line_;
};

// ---------------------------------------------------------------------------------------------
// OBJ

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

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool parse_ply_type(std::string_view s, PlyType& type) {
  static const std::pair<std::string_view, PlyType> kNames[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [name, t] : kNames) {
    if (s == name) {
      type = t;
      return true;
    }
  }
  return false;
}

std::size_t byte_size(PlyType t) {
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

bool is_integer(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

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

PlyHeader parse_ply_header(const fs::path& path, std::string_view text) {
  PlyHeader header;
  LineReader lines(text);
  std::string_view line;
  if (!lines.next(line) || split(line) != Tokens{"ply"}) {
    fail_at(path, 1, "expected 'ply' as the first line");
  }
  bool have_format = false;
  while (lines.next(line)) {
    const long ln = lines.line();
    const Tokens tok = split(line);
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "end_header") {
      if (!have_format) fail_at(path, ln, "expected a 'format' line before end_header");
      header.body_offset = lines.offset();
      header.header_lines = ln;
      return header;
    }
    if (tok[0] == "format") {
      static const char* kExpected =
          "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'";
      if (tok.size() != 3 || tok[2] != "1.0") fail_at(path, ln, kExpected);
      if (tok[1] == "ascii")
        header.format = PlyFormat::kAscii;
      else if (tok[1] == "binary_little_endian")
        header.format = PlyFormat::kBinaryLittleEndian;
      else if (tok[1] == "binary_big_endian")
        header.format = PlyFormat::kBinaryBigEndian;
      else
        fail_at(path, ln, kExpected);
      have_format = true;
    } else if (tok[0] == "element") {
      PlyElement element;
      if (tok.size() != 3 || !parse_number(tok[2], element.count) || element.count < 0) {
        fail_at(path, ln, "expected 'element <name> <count>' with a count >= 0");
      }
      element.name = tok[1];
      element.line = ln;
      header.elements.push_back(std::move(element));
    } else if (tok[0] == "property") {
      if (header.elements.empty()) fail_at(path, ln, "property before any element");
      PlyProperty p;
      const bool list = tok.size() >= 2 && tok[1] == "list";
      if (list ? tok.size() != 5 || !parse_ply_type(tok[2], p.count_type) ||
                     !is_integer(p.count_type) || !parse_ply_type(tok[3], p.type)
               : tok.size() != 3 || !parse_ply_type(tok[1], p.type)) {
        fail_at(path, ln,
                "expected 'property <type> <name>' or 'property list <integer type> <type> "
                "<name>' with types char uchar short ushort int uint float double");
      }
      p.is_list = list;
      p.name = tok.back();
      header.elements.back().properties.push_back(std::move(p));
    } else {
      fail_at(path, ln, "unknown header line '" + std::string(tok[0]) + "'");
    }
  }
  fail_at(path, lines.line(), "file ends before 'end_header'");
}

// Which element and property indices hold the data we keep.
struct PlyLayout {
  int vertex = -1, face = -1;
  int x = -1, y = -1, z = -1, u = -1, v = -1, indices = -1;
};

int find_property(const PlyElement& e, std::string_view name) {
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    if (e.properties[k].name == name) return static_cast<int>(k);
  }
  return -1;
}

PlyLayout ply_layout(const fs::path& path, const PlyHeader& h) {
  PlyLayout layout;
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    if (h.elements[e].name == "vertex" && layout.vertex < 0) layout.vertex = static_cast<int>(e);
    if (h.elements[e].name == "face" && layout.face < 0) layout.face = static_cast<int>(e);
  }
  if (layout.vertex < 0) fail_at(path, h.header_lines, "no 'element vertex' in the header");
  const PlyElement& vertex = h.elements[layout.vertex];
  if (vertex.count > std::numeric_limits<int>::max()) {
    fail_at(path, vertex.line, "too many vertices for 32-bit indices");
  }
  int* xyz[3] = {&layout.x, &layout.y, &layout.z};
  for (int k = 0; k < 3; ++k) {
    const char name[2] = {static_cast<char>('x' + k), '\0'};
    *xyz[k] = find_property(vertex, name);
    if (*xyz[k] < 0 || vertex.properties[*xyz[k]].is_list) {
      fail_at(path, vertex.line,
              std::string("element vertex has no scalar property '") + name +
                  "'; x, y and z are required");
    }
  }
  for (auto [u, v] : {std::pair{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}}) {
    const int iu = find_property(vertex, u), iv = find_property(vertex, v);
    if (iu >= 0 && iv >= 0 && !vertex.properties[iu].is_list && !vertex.properties[iv].is_list) {
      layout.u = iu;
      layout.v = iv;
      break;
    }
  }
  if (layout.face >= 0) {
    const PlyElement& face = h.elements[layout.face];
    layout.indices = find_property(face, "vertex_indices");
    if (layout.indices < 0) layout.indices = find_property(face, "vertex_index");
    if (layout.indices < 0 || !face.properties[layout.indices].is_list ||
        !is_integer(face.properties[layout.indices].type)) {
      fail_at(path, face.line,
              "element face needs an integer list property 'vertex_indices' or 'vertex_index'");
    }
  }
  return layout;
}

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

SurfaceMesh read_ply(const fs::path& path, std::string_view text) {
  const PlyHeader header = parse_ply_header(path, text);
  const PlyLayout layout = ply_layout(path, header);
  const std::string_view body = text.substr(header.body_offset);
  if (header.format == PlyFormat::kAscii) {
    AsciiSource src(path, body, header.header_lines);
    return read_ply_body(src, header, layout);
  }
  BinarySource src(path, body, header.format == PlyFormat::kBinaryBigEndian);
  return read_ply_body(src, header, layout);
}

// ---------------------------------------------------------------------------------------------
// Writing

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

// Writes to "<path>.tmp" and renames over `path`, so readers never see a partial file.
void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& body) {
  fs::path tmp = path;
  tmp += ".tmp";
  std::error_code ignored;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open " + tmp.string());
    out.imbue(std::locale::classic());
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    try {
      body(out);
    } catch (...) {
      out.close();
      fs::remove(tmp, ignored);
      throw;
    }
    out.close();
    if (!out) {
      fs::remove(tmp, ignored);
      throw std::runtime_error(path.string() + ": writing " + tmp.string() + " failed");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ignored);
    throw std::runtime_error(path.string() + ": cannot rename " + tmp.string() + ": " +
                             ec.message());
  }
}

template <class T>
void put_little_endian(std::ostream& out, T value) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + sizeof(T));
  out.write(b, sizeof(T));
}

// Orthonormal in-plane axes for unit normal n: u = world x projected into the plane (world y
// when the plane is normal to x), v = n x u.
std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
  Vec3 u = Vec3::UnitX() - n.x() * n;
  if (u.norm() < 1e-6) u = Vec3::UnitY() - n.y() * n;
  u.normalize();
  return {u, n.cross(u)};
}

std::vector<Vec2> project_onto_best_fit_plane(const std::vector<Vec3>& p, double tolerance) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].allFinite()) {
      throw std::invalid_argument("sheet_mesh_from_flat: vertex " + std::to_string(i) +
                                  " is not finite");
    }
  }
  std::vector<Vec2> uv(p.size());
  const bool horizontal =
      std::all_of(p.begin(), p.end(), [&](const Vec3& q) { return q.z() == p[0].z(); });
  if (horizontal) {  // exact: no rounding from a fitted normal
    for (std::size_t i = 0; i < p.size(); ++i) uv[i] = p[i].head<2>();
    return uv;
  }
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& q : p) centroid += q;
  centroid /= static_cast<double>(p.size());
  Mat3 covariance = Mat3::Zero();
  for (const Vec3& q : p) covariance += (q - centroid) * (q - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(covariance);
  Vec3 n = eigen.eigenvectors().col(0);  // eigenvalues ascend: col 0 is the normal
  // Sign the normal towards +z (vertical planes: +y, then +x) so v = n x u is predictable.
  const double sign = std::abs(n.z()) > 1e-9 ? n.z() : std::abs(n.y()) > 1e-9 ? n.y() : n.x();
  if (sign < 0) n = -n;
  std::size_t worst = 0;
  double worst_distance = -1.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = std::abs((p[i] - centroid).dot(n));
    if (d > worst_distance) {
      worst_distance = d;
      worst = i;
    }
  }
  if (worst_distance > tolerance) {
    throw std::invalid_argument("sheet_mesh_from_flat: mesh is not flat: vertex " +
                                std::to_string(worst) + " is " + short_number(worst_distance) +
                                " m from the best-fit plane (tolerance " + short_number(tolerance) +
                                " m)");
  }
  const auto [u, v] = plane_axes(n);
  for (std::size_t i = 0; i < p.size(); ++i) uv[i] = Vec2(p[i].dot(u), p[i].dot(v));
  return uv;
}

// Flips all triangles if all are clockwise; mixed orientation is an error.
void orient_counter_clockwise(SheetMesh& sheet) {
  int ccw = 0, cw = 0, first_ccw = -1, first_cw = -1;
  const int n = sheet.vertex_count();
  for (int t = 0; t < sheet.triangle_count(); ++t) {
    const auto& tri = sheet.triangles[t];
    if (std::any_of(tri.begin(), tri.end(), [n](int i) { return i < 0 || i >= n; })) continue;
    const double area = sheet.rest_area(t);
    if (area > 0 && ccw++ == 0) first_ccw = t;
    if (area < 0 && cw++ == 0) first_cw = t;
  }
  if (cw == 0) return;
  if (ccw == 0) {
    for (auto& tri : sheet.triangles) std::swap(tri[1], tri[2]);
    return;
  }
  const bool mostly_ccw = ccw >= cw;
  throw std::invalid_argument(
      "sheet_mesh_from_flat: triangles have mixed orientation in (u, v): triangle " +
      std::to_string(mostly_ccw ? first_cw : first_ccw) + " is " +
      (mostly_ccw ? "clockwise" : "counter-clockwise") + " but " +
      std::to_string(std::max(ccw, cw)) + " of " + std::to_string(sheet.triangle_count()) +
      " are not");
}

}  // namespace

SurfaceMesh read_surface_mesh(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".obj" && ext != ".ply") {
    throw std::runtime_error(path.string() + ": unknown mesh extension, expected .obj or .ply");
  }
  const std::string text = read_whole_file(path);
  return ext == ".obj" ? read_obj(path, text) : read_ply(path, text);
}

void write_ply(const fs::path& path, const SurfaceMesh& mesh,
               const std::vector<VertexScalar>& scalars, bool binary) {
  check_for_writing(path, mesh, scalars);
  const bool has_uv = !mesh.uv.empty();
  write_atomically(path, [&](std::ostream& out) {
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
  write_atomically(path, [&](std::ostream& out) {
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

void write_surface_mesh(const fs::path& path, const SurfaceMesh& mesh) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return write_ply(path, mesh);
  if (ext == ".obj") return write_obj(path, mesh);
  throw std::invalid_argument(path.string() + ": unknown mesh extension, expected .obj or .ply");
}

SheetMesh sheet_mesh_from_flat(const SurfaceMesh& mesh, double flatness_tolerance_m) {
  if (!(flatness_tolerance_m >= 0.0)) {
    throw std::invalid_argument("sheet_mesh_from_flat: flatness_tolerance_m must be >= 0");
  }
  if (mesh.positions.empty() || mesh.triangles.empty()) {
    throw std::invalid_argument("sheet_mesh_from_flat: mesh has no vertices or no triangles");
  }
  if (!mesh.uv.empty() && mesh.uv.size() != mesh.positions.size()) {
    throw std::invalid_argument("sheet_mesh_from_flat: uv has " + std::to_string(mesh.uv.size()) +
                                " entries for " + std::to_string(mesh.positions.size()) +
                                " vertices");
  }
  SheetMesh sheet;
  sheet.triangles = mesh.triangles;
  sheet.rest_uv =
      mesh.uv.empty() ? project_onto_best_fit_plane(mesh.positions, flatness_tolerance_m) : mesh.uv;
  orient_counter_clockwise(sheet);
  validate_sheet_mesh(sheet);
  return sheet;
}

SurfaceMesh surface_from_positions(const SheetMesh& sheet, const VecX& x) {
  const int n = sheet.vertex_count();
  if (x.size() != 3 * static_cast<Eigen::Index>(n)) {
    throw std::invalid_argument("surface_from_positions: x has " + std::to_string(x.size()) +
                                " entries, expected 3 x " + std::to_string(n));
  }
  SurfaceMesh mesh;
  mesh.positions.resize(n);
  for (int i = 0; i < n; ++i) mesh.positions[i] = vertex(x, i);
  mesh.triangles = sheet.triangles;
  mesh.uv = sheet.rest_uv;
  return mesh;
}

}  // namespace twin
