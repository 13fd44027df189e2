#pragma once
// The shared-memory layout of one emulated V4L2 node (sim_hw's user-space V4L2 emulation, for CI
// without /dev/video): a producer (EmulatedV4l2Node) publishes frames, the LD_PRELOAD shim's
// device model reads them. POSIX shm object "/<name>":
//   Header (one 4 KiB page) | slot 0 | slot 1 | ... each slot = SlotHeader (64 B) + frame bytes.
// Frames go round the slots; each slot is a seqlock (odd count while the producer writes it), so
// a reader copies, then checks the count did not move, and never keeps a torn frame. (The copy
// itself races with a writer by design, as every seqlock's does; only its result is checked.)
// Free of the project's libraries and of interposed libc calls (it uses syscall() for mmap,
// munmap and close), so the shim can compile it in and call it under its own locks.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>

namespace sim_hw::v4l2_shm {

constexpr std::uint32_t kMagic = 0x34565050;  // "PPV4"
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kSlotCount = 8;
constexpr std::size_t kHeaderBytes = 4096;
constexpr std::size_t kSlotHeaderBytes = 64;

struct Header {
  std::atomic<std::uint32_t> magic;  // stored last by the producer: the node is ready
  std::uint32_t version;
  std::uint32_t pixel_format;  // V4L2 fourcc
  std::uint32_t width, height, bytes_per_line, frame_bytes;  // px, bytes
  std::uint32_t fps;
  std::uint32_t slot_count;
  std::uint32_t slot_stride;  // bytes per slot, header included
  char driver[16], card[32], bus_info[32];
  std::atomic<std::uint32_t> alive;       // 0 once the producer marks the device dead (unplug)
  std::atomic<std::uint64_t> published;  // frames published so far; the newest is number published-1
};

struct SlotHeader {
  std::atomic<std::uint64_t> seqlock;  // odd while being written
  std::uint64_t number;                // publish count of the frame in the slot
  std::uint64_t sequence;              // device frame counter (gaps = dropped frames)
  std::int64_t timestamp_us;           // CLOCK_MONOTONIC, as uvcvideo stamps buffers
  std::uint32_t bytes_used;
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "shared atomics must be lock free");
static_assert(sizeof(Header) <= kHeaderBytes && sizeof(SlotHeader) <= kSlotHeaderBytes);

struct FrameInfo {
  std::uint64_t sequence = 0;
  std::int64_t timestamp_us = 0;
  std::uint32_t bytes_used = 0;
};

// A mapping of a node's shm object.
struct Mapping {
  Header* header = nullptr;
  std::size_t bytes = 0;
};

std::size_t total_bytes(std::uint32_t slot_stride, std::uint32_t slot_count);

// Maps an existing node read-write. Returns 0 or -errno: ENOENT (no such node), ENODEV (not
// ready, wrong magic/version, or dead).
int attach(const std::string& name, Mapping& out);
void detach(Mapping& mapping);

// Copies frame number `number` into dst (capacity bytes). False when that frame is not in the
// ring (not yet published, or overwritten).
bool read_frame(const Header& header, std::uint64_t number, std::uint8_t* dst, std::size_t capacity,
                FrameInfo& info);

// Producer side: writes the next frame into its slot and publishes it.
void write_frame(Header& header, const std::uint8_t* data, std::size_t bytes, std::uint64_t sequence,
                 std::int64_t timestamp_us);

// "/" + name, as shm_open wants it.
std::string shm_path(const std::string& name);

}  // namespace sim_hw::v4l2_shm
