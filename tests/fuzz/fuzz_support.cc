#include "tests/fuzz/fuzz_support.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace fuzz {
namespace fs = std::filesystem;

namespace {

struct Scratch {
  fs::path path;
  Scratch() {
    std::string pattern = (fs::temp_directory_path() / "prepreg_fuzz_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      std::fprintf(stderr, "fuzz: cannot make a scratch directory under %s\n",
                   fs::temp_directory_path().c_str());
      std::abort();
    }
    path = pattern;
  }
  ~Scratch() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

bool safe_name(std::string_view name) {
  if (name.empty() || name.size() > 64 || name.front() == '/' || name.back() == '/') return false;
  int slashes = 0;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-' || c == '/';
    if (!ok) return false;
    if (c == '/') ++slashes;
  }
  if (slashes > 1) return false;
  // No "." or ".." component: everything stays inside the scratch directory.
  for (std::size_t start = 0; start <= name.size();) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    const std::string_view part = name.substr(start, end - start);
    if (part == "." || part == "..") return false;
    start = end + 1;
  }
  return true;
}

}  // namespace

const fs::path& scratch_dir() {
  static Scratch scratch;
  return scratch.path;
}

void clear_scratch() {
  std::error_code ignored;
  for (const auto& entry : fs::directory_iterator(scratch_dir())) fs::remove_all(entry.path(), ignored);
}

fs::path write_scratch_file(const std::string& name, std::string_view bytes) {
  const fs::path path = scratch_dir() / name;
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

std::vector<fs::path> write_scratch_files(const std::uint8_t* data, std::size_t size,
                                          const std::string& first_name) {
  static constexpr std::string_view kMarker = "%%FILE ";
  clear_scratch();
  const std::string_view text = as_text(data, size);
  std::vector<fs::path> written;
  std::string name = first_name;
  std::size_t begin = 0;
  while (true) {
    // The next marker at the start of a line.
    std::size_t marker = text.find(kMarker, begin);
    while (marker != std::string_view::npos && marker > 0 && text[marker - 1] != '\n') {
      marker = text.find(kMarker, marker + 1);
    }
    // The line break before a marker line belongs to the marker, so a file may end without one.
    const std::size_t end = marker == std::string_view::npos ? text.size() : (marker > begin ? marker - 1 : marker);
    if (safe_name(name)) {
      const fs::path path = scratch_dir() / name;
      // A name used twice, or a file where a folder is wanted, is skipped like a bad name.
      std::error_code ec;
      const bool parent_ok =
          !fs::exists(path.parent_path(), ec) || fs::is_directory(path.parent_path(), ec);
      if (parent_ok && !fs::exists(path, ec)) {
        written.push_back(write_scratch_file(name, text.substr(begin, end - begin)));
      }
    }
    if (marker == std::string_view::npos) break;
    const std::size_t name_begin = marker + kMarker.size();
    std::size_t line_end = text.find('\n', name_begin);
    if (line_end == std::string_view::npos) line_end = text.size();
    name = std::string(text.substr(name_begin, line_end - name_begin));
    begin = std::min(line_end + 1, text.size());
    if (line_end == text.size()) break;
  }
  return written;
}

void require_named(const std::exception& error, const std::string& expected) {
  const std::string what = error.what();
  if (what.find(expected) != std::string::npos) return;
  std::fprintf(stderr, "fuzz: an error that does not name '%s': %s\n", expected.c_str(), what.c_str());
  std::abort();
}

}  // namespace fuzz
