#pragma once
// What every libFuzzer harness of the project shares (issue 36; docs/fuzzing.md): a scratch
// directory per fuzzing process for readers that take paths, inputs that hold several files, and
// the rule that a reader's error names what it read.
//
// A harness calls a reader the way the cell, a tool or a test does, on bytes the fuzzer makes.
// Errors the reader documents (std::exception subclasses with a message) are the expected way to
// refuse input; a crash, a sanitizer report, a leak, a hang or an error that does not say which
// file it is about are findings.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace fuzz {

// This process's scratch directory (made on first use under $TMPDIR, removed at exit).
const std::filesystem::path& scratch_dir();

// Empties the scratch directory (each input starts from nothing).
void clear_scratch();

// Writes `bytes` to scratch/name (sub-directories made as needed) and returns the path.
std::filesystem::path write_scratch_file(const std::string& name, std::string_view bytes);

// An input that holds several files: a line "%%FILE <name>" starts the next file (the line break
// before it is not part of the previous file), and whatever comes before the first such line is
// the file `first_name`. Names are relative paths of
// letters, digits and "._-" with at most one '/' (nothing outside the scratch directory); a
// section whose name is not that is skipped. Writes every file into the (cleared) scratch
// directory and returns their paths in input order.
std::vector<std::filesystem::path> write_scratch_files(const std::uint8_t* data, std::size_t size,
                                                       const std::string& first_name);

// A refused input must say what it is about: aborts (a finding, with the message) unless the
// error's text contains `expected` (a path or a name the reader was given).
void require_named(const std::exception& error, const std::string& expected);

// Runs `read`; when it throws, the error must name `expected` (require_named).
template <typename Read>
void read_or_named_error(const std::string& expected, Read&& read) {
  try {
    read();
  } catch (const std::exception& error) {
    require_named(error, expected);
  }
}

// The input's files (write_scratch_files, `first_name` first), then `read(path of first_name)`;
// when it throws, the error must name a file of the scratch directory.
template <typename Read>
void read_files_or_named_error(const std::uint8_t* data, std::size_t size, const std::string& first_name,
                               Read&& read) {
  write_scratch_files(data, size, first_name);
  const std::string first = (scratch_dir() / first_name).string();
  read_or_named_error(scratch_dir().string(), [&] { read(first); });
}

// The bytes as text.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace fuzz
