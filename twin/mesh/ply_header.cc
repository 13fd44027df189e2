#include "twin/mesh/ply_header.h"

#include <limits>
#include <string>
#include <utility>

#include "twin/mesh/mesh_io_internal.h"

namespace twin::internal {
namespace {

namespace fs = std::filesystem;

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

int find_property(const PlyElement& e, std::string_view name) {
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    if (e.properties[k].name == name) return static_cast<int>(k);
  }
  return -1;
}

}  // namespace

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

}  // namespace twin::internal
