#include "sim_hw/v4l2_shm_layout.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

namespace sim_hw::v4l2_shm {
namespace {

SlotHeader* slot(const Header& h, std::uint64_t number) {
  auto* base = reinterpret_cast<std::uint8_t*>(const_cast<Header*>(&h)) + kHeaderBytes;
  return reinterpret_cast<SlotHeader*>(base + (number % h.slot_count) * h.slot_stride);
}

}  // namespace

std::size_t total_bytes(std::uint32_t slot_stride, std::uint32_t slot_count) {
  return kHeaderBytes + static_cast<std::size_t>(slot_stride) * slot_count;
}

std::string shm_path(const std::string& name) { return name.starts_with('/') ? name : "/" + name; }

int attach(const std::string& name, Mapping& out) {
  const int fd = ::shm_open(shm_path(name).c_str(), O_RDWR, 0);
  if (fd < 0) return -errno;
  struct stat st {};
  if (::fstat(fd, &st) < 0 || static_cast<std::size_t>(st.st_size) < kHeaderBytes) {
    ::syscall(SYS_close, fd);
    return -ENODEV;
  }
  const long addr = ::syscall(SYS_mmap, nullptr, static_cast<std::size_t>(st.st_size),
                              PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int mmap_errno = errno;
  ::syscall(SYS_close, fd);
  if (addr == -1) return -mmap_errno;
  auto* h = reinterpret_cast<Header*>(addr);
  const bool ready = h->magic.load(std::memory_order_acquire) == kMagic && h->version == kVersion &&
                     h->alive.load() && total_bytes(h->slot_stride, h->slot_count) <= static_cast<std::size_t>(st.st_size);
  if (!ready) {
    ::syscall(SYS_munmap, addr, static_cast<std::size_t>(st.st_size));
    return -ENODEV;
  }
  out.header = h;
  out.bytes = static_cast<std::size_t>(st.st_size);
  return 0;
}

void detach(Mapping& m) {
  if (m.header) ::syscall(SYS_munmap, m.header, m.bytes);
  m = Mapping{};
}

bool read_frame(const Header& h, std::uint64_t number, std::uint8_t* dst, std::size_t capacity, FrameInfo& info) {
  SlotHeader* s = slot(h, number);
  const auto* data = reinterpret_cast<const std::uint8_t*>(s) + kSlotHeaderBytes;
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const std::uint64_t before = s->seqlock.load(std::memory_order_acquire);
    if (before & 1) {  // the producer is writing this slot right now
      std::this_thread::yield();
      continue;
    }
    const std::uint64_t in_slot = s->number;
    FrameInfo copy{s->sequence, s->timestamp_us, s->bytes_used};
    if (in_slot == number) std::memcpy(dst, data, std::min<std::size_t>(copy.bytes_used, capacity));
    std::atomic_thread_fence(std::memory_order_acquire);
    if (s->seqlock.load(std::memory_order_relaxed) != before) continue;
    if (in_slot != number) return false;
    info = copy;
    info.bytes_used = static_cast<std::uint32_t>(std::min<std::size_t>(copy.bytes_used, capacity));
    return true;
  }
  return false;
}

void write_frame(Header& h, const std::uint8_t* data, std::size_t bytes, std::uint64_t sequence,
                 std::int64_t timestamp_us) {
  const std::uint64_t number = h.published.load(std::memory_order_relaxed);
  SlotHeader* s = slot(h, number);
  const std::uint64_t count = s->seqlock.load(std::memory_order_relaxed);
  s->seqlock.store(count + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  s->number = number;
  s->sequence = sequence;
  s->timestamp_us = timestamp_us;
  s->bytes_used = static_cast<std::uint32_t>(std::min<std::size_t>(bytes, h.frame_bytes));
  std::memcpy(reinterpret_cast<std::uint8_t*>(s) + kSlotHeaderBytes, data, s->bytes_used);
  s->seqlock.store(count + 2, std::memory_order_release);
  h.published.store(number + 1, std::memory_order_release);
}

}  // namespace sim_hw::v4l2_shm
