#pragma once
// One V4L2 video-capture node streamed with mmap buffers (the D415 exposes depth and colour as
// separate uvcvideo nodes). All system calls go through a V4l2Io, so the same code runs on a real
// device, the LD_PRELOAD emulation in CI, or a fake in tests. Errors name the device path, the
// ioctl and strerror. Never throws.

#include <cstdint>
#include <string>
#include <vector>

#include "drivers/depth_camera.h"
#include "drivers/v4l2_io.h"

namespace drivers {

struct V4l2StreamSpec {
  std::string path;               // e.g. /dev/video0 or /dev/v4l/by-id/...
  std::uint32_t pixel_format = 0;  // V4L2_PIX_FMT_Z16, V4L2_PIX_FMT_YUYV
  int width = 0, height = 0;      // px
  int fps = 0;                    // frames/s
  int bytes_per_pixel = 2;        // Z16 and YUYV both 2
};

struct CapturedImage {
  std::vector<std::uint8_t> data;  // rows without driver padding: width * bytes_per_pixel each
  std::uint64_t sequence = 0;      // driver frame counter
  std::int64_t timestamp_us = 0;   // buffer timestamp (uvcvideo: CLOCK_MONOTONIC at capture)
  bool driver_error = false;       // V4L2_BUF_FLAG_ERROR: the driver says the data is damaged
  bool monotonic_clock = false;    // V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC: comparable with steady_clock
};

enum class CaptureStatus { kFrame, kTimeout, kLost };

class V4l2CaptureNode {
 public:
  static constexpr int kBufferCount = 4;

  explicit V4l2CaptureNode(V4l2Io& io) : io_(io) {}
  ~V4l2CaptureNode() { close(); }
  V4l2CaptureNode(const V4l2CaptureNode&) = delete;
  V4l2CaptureNode& operator=(const V4l2CaptureNode&) = delete;

  // open (non-blocking), QUERYCAP (capture + streaming), S_FMT (exact format and size or fail),
  // S_PARM (fps), REQBUFS (mmap), QUERYBUF + mmap each buffer.
  DriverResult open(const V4l2StreamSpec& spec);
  // QBUF every buffer, STREAMON.
  DriverResult start();
  // Waits up to timeout_ms (0 = only what is ready) for a filled buffer: poll, DQBUF, copy,
  // QBUF again. kLost when the device went away (ENODEV, EIO, ...); error() says why.
  CaptureStatus next(int timeout_ms, CapturedImage& out);
  // STREAMOFF, munmap, close; safe to call at any time.
  void close();

  bool is_open() const { return fd_ >= 0; }
  const std::string& error() const { return error_; }
  const V4l2StreamSpec& spec() const { return spec_; }

 private:
  int xioctl(unsigned long request, void* arg);  // retries on EINTR
  DriverResult fail(const char* what, int err);
  bool copy_out(std::uint32_t index, std::uint32_t bytes_used, CapturedImage& out);

  struct Buffer {
    void* start = nullptr;
    std::size_t length = 0;
  };
  V4l2Io& io_;
  V4l2StreamSpec spec_;
  int fd_ = -1;
  bool streaming_ = false;
  std::uint32_t bytes_per_line_ = 0;
  std::vector<Buffer> buffers_;
  std::string error_;
};

// "Z16 " style text of a fourcc, for messages.
std::string fourcc_text(std::uint32_t fourcc);

}  // namespace drivers
