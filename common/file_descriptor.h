#pragma once
// A POSIX file descriptor that closes itself, and a write that does not stop short: the two
// pieces durable_file.cc and append_journal.cc both need.

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

}  // namespace prepreg
