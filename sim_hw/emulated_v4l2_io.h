#pragma once
// drivers::V4l2Io served in-process by the V4L2 device emulation (no LD_PRELOAD): paths in the
// map open emulated nodes (EmulatedV4l2Device over a producer's shm node); any other path fails
// with ENOENT. Lets a test or a tool run the real V4L2 back-end against emulated nodes inside one
// process, and lets a test wrap it to inject faults (EINTR, EIO, ...).

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "drivers/v4l2_io.h"
#include "sim_hw/emulated_v4l2_device.h"

namespace sim_hw {

class EmulatedV4l2Io : public drivers::V4l2Io {
 public:
  // device path -> shm node name, e.g. {"/dev/video0", "prepreg_cam0_depth"}.
  explicit EmulatedV4l2Io(std::map<std::string, std::string> shm_by_path);

  int open(const char* path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(std::size_t length, int fd, off_t offset) override;
  int munmap(void* address, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;

  int open_fds() const;

 private:
  std::shared_ptr<EmulatedV4l2Device> device(int fd) const;

  std::map<std::string, std::string> shm_by_path_;
  mutable std::mutex mutex_;
  std::map<int, std::shared_ptr<EmulatedV4l2Device>> devices_;
  int next_fd_ = 1000;  // fake fd numbers, never reused
};

}  // namespace sim_hw
