#pragma once
// The system calls the V4L2 back-end makes, behind an interface so the capture code can run
// against a fake device (tests) or an in-process emulation. Each call follows the libc
// convention: -1 (or MAP_FAILED) with errno set on failure.
//
// LibcV4l2Io calls libc's open/ioctl/mmap/poll directly, NOT libv4l2's v4l2_ioctl family: the
// D415's Z16 and YUYV need no format conversion, and libv4l2 issues syscall() directly, which an
// LD_PRELOAD shim (sim_hw's user-space V4L2 emulation in CI) cannot interpose.

#include <poll.h>
#include <sys/types.h>

#include <cstddef>

namespace drivers {

class V4l2Io {
 public:
  virtual ~V4l2Io() = default;
  virtual int open(const char* path, int flags) = 0;
  virtual int close(int fd) = 0;
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  // mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset).
  virtual void* mmap(std::size_t length, int fd, off_t offset) = 0;
  virtual int munmap(void* address, std::size_t length) = 0;
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
};

class LibcV4l2Io : public V4l2Io {
 public:
  int open(const char* path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(std::size_t length, int fd, off_t offset) override;
  int munmap(void* address, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;
};

}  // namespace drivers
