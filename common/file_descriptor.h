#pragma once
// A POSIX file descriptor that closes itself, a write that does not stop short, and the error
// naming a file and the system's reason: what durable_file.cc and append_journal.cc both need.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace prepreg {

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd = -1) : fd_(fd) {}
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  FileDescriptor& operator=(FileDescriptor&& other) noexcept;
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() { close(); }

  explicit operator bool() const { return fd_ >= 0; }
  int get() const { return fd_; }
  // Closes it; returns errno when close failed (an error of a delayed write may show only here),
  // else 0.
  int close();

 private:
  int fd_;
};

// Writes every byte, retrying after signals and short writes; returns errno on failure, else 0.
int write_all(int fd, std::string_view bytes);

// "<path>: <what>: <strerror(error)>".
std::runtime_error file_error(const std::filesystem::path& path, const std::string& what, int error);

}  // namespace prepreg
