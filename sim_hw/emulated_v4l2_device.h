#pragma once
// The device model behind one open emulated V4L2 node: answers the ioctls a uvcvideo D415 node
// answers to a capture program (QUERYCAP, ENUM_FMT, G/S/TRY_FMT, G/S_PARM, REQBUFS (MMAP),
// QUERYBUF, QBUF, DQBUF, STREAMON/OFF), hands out its buffers for mmap, and reports poll
// readiness, over the frames a producer publishes into the node's shared memory. Used by the
// LD_PRELOAD shim (one per emulated fd). Thread-safe; no exceptions escape; calls no interposed
// libc function (the shim calls it while serving one).
//
// Like vb2/uvcvideo: only the node's one format and size exist (S_FMT adjusts to them), one frame
// rate; buffers are filled in queue order with the oldest undelivered frame, at most as many
// frames behind as there are buffers (older ones are dropped, seen as sequence gaps); once the
// producer marks the node dead every ioctl fails with ENODEV and poll reports POLLERR.

#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include "sim_hw/v4l2_shm_layout.h"

namespace sim_hw {

class EmulatedV4l2Device {
 public:
  EmulatedV4l2Device() = default;
  ~EmulatedV4l2Device();
  EmulatedV4l2Device(const EmulatedV4l2Device&) = delete;
  EmulatedV4l2Device& operator=(const EmulatedV4l2Device&) = delete;

  // Attaches to node `shm_name`; 0 or -errno (ENOENT: no such node, ENODEV: dead or not ready).
  int open(const std::string& shm_name, bool non_blocking);
  // 0 or -errno (ENOTTY for ioctls a capture node does not have).
  int ioctl(unsigned long request, void* arg);
  // The buffer at `offset` (from QUERYBUF), or nullptr (errno EINVAL).
  void* map(std::size_t length, std::uint64_t offset);
  // True when `address` is one of this device's mapped buffers (then it is unmapped).
  bool unmap(const void* address);
  bool has_mapped_buffers() const;
  // poll(2) revents for `events`.
  short poll_events(short events);
  void set_non_blocking(bool non_blocking);

 private:
  struct Buffer {
    std::vector<std::uint8_t> memory;
    std::uint64_t offset = 0;
    bool queued = false, mapped = false;
  };
  bool alive() const;
  int dequeue(void* arg);  // with mutex_ held
  bool frame_ready();      // with mutex_ held
  void fill_format(void* format) const;

  mutable std::mutex mutex_;
  v4l2_shm::Mapping map_;
  bool non_blocking_ = false;
  bool streaming_ = false;
  std::vector<Buffer> buffers_;
  std::deque<std::uint32_t> queue_;  // queued buffer indices, in QBUF order
  std::uint64_t next_number_ = 0;    // publish number of the next frame to deliver
};

}  // namespace sim_hw
