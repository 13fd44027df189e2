#pragma once
// Helpers shared by the text-file readers and writers of the twin (the meshes behind
// twin/mesh/mesh_io.h, the xyz point files of twin/trials/trial.h). Not a public API.

#include <charconv>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "twin/mesh/mesh_io.h"

namespace twin::internal {

using Tokens = std::vector<std::string_view>;

// Throws std::runtime_error("<path>:<line>: <what>"), the text-file error format of mesh_io.h.
[[noreturn]] void fail_at(const std::filesystem::path& path, long line, const std::string& what);

// The extension including the dot, lower-cased (".obj" for "a.OBJ").
std::string lower_extension(const std::filesystem::path& path);

// The whole file as bytes; throws std::runtime_error naming the path if it cannot be read.
std::string read_whole_file(const std::filesystem::path& path);

// Whitespace-separated tokens of a line, viewing into it.
Tokens split(std::string_view line);

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
  bool next(std::string_view& line);
  long line() const { return line_; }          // number of the line last returned
  std::size_t offset() const { return pos_; }  // byte offset just after it

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  long line_;
};

// The format readers, given the file's whole contents; `path` is only used in error messages.
SurfaceMesh read_obj(const std::filesystem::path& path, std::string_view text);
SurfaceMesh read_ply(const std::filesystem::path& path, std::string_view text);

}  // namespace twin::internal
