// The V4L2 back-end's real code (capture nodes, format negotiation, DQBUF, loss and reopen)
// against the user-space V4L2 emulation served in-process (sim_hw::EmulatedV4l2Io), wrapped to
// inject errno faults. The LD_PRELOAD path is tested in tests/sim_hw/v4l2_emulation_test.cc.

#include <linux/videodev2.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <deque>
#include <functional>
#include <limits>
#include <thread>

#include "drivers/monitored_depth_camera.h"
#include "drivers/v4l2_d415_camera.h"
#include "drivers/yuyv_color.h"
#include "sim_hw/emulated_v4l2_io.h"
#include "sim_hw/emulated_v4l2_node.h"

namespace {

constexpr int kW = 64, kH = 48;

// Forwards to the emulation; ioctls listed in `faults` fail once each with the given errno.
class FaultInjectingIo : public drivers::V4l2Io {
 public:
  explicit FaultInjectingIo(std::map<std::string, std::string> nodes) : io_(std::move(nodes)) {}
  std::map<unsigned long, std::deque<int>> faults;
  std::map<unsigned long, int> calls;
  std::function<void(v4l2_buffer&)> on_dqbuf;  // alters what a successful DQBUF hands back

  int open(const char* p, int f) override { return io_.open(p, f); }
  int close(int fd) override { return io_.close(fd); }
  int ioctl(int fd, unsigned long request, void* arg) override {
    ++calls[request];
    auto it = faults.find(request);
    if (it != faults.end() && !it->second.empty()) {
      errno = it->second.front();
      it->second.pop_front();
      return -1;
    }
    const int r = io_.ioctl(fd, request, arg);
    if (r == 0 && request == VIDIOC_DQBUF && on_dqbuf) on_dqbuf(*static_cast<v4l2_buffer*>(arg));
    return r;
  }
  void* mmap(std::size_t l, int fd, off_t o) override { return io_.mmap(l, fd, o); }
  int munmap(void* a, std::size_t l) override { return io_.munmap(a, l); }
  int poll(pollfd* fds, nfds_t n, int t) override { return io_.poll(fds, n, t); }
  int open_fds() const { return io_.open_fds(); }

 private:
  sim_hw::EmulatedV4l2Io io_;
};

std::vector<std::uint16_t> depth_pattern(std::uint64_t k) {
  std::vector<std::uint16_t> d(kW * kH);
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = static_cast<std::uint16_t>(400 + (i * 7 + k * 13) % 3000);
  return d;
}

// Pixel pairs share a colour (YUYV keeps one chroma per pair).
std::vector<std::uint8_t> rgb_pattern(std::uint64_t k) {
  std::vector<std::uint8_t> rgb(kW * kH * 3);
  for (std::size_t p = 0; p < static_cast<std::size_t>(kW * kH); ++p) {
    const std::size_t pair = p / 2;
    rgb[3 * p + 0] = static_cast<std::uint8_t>(30 + (pair * 5 + k) % 190);
    rgb[3 * p + 1] = static_cast<std::uint8_t>(40 + (pair * 3 + 2 * k) % 170);
    rgb[3 * p + 2] = static_cast<std::uint8_t>(50 + (pair * 11 + 3 * k) % 150);
  }
  return rgb;
}

struct Rig {
  std::string prefix = "prepreg_drvtest_" + std::to_string(::getpid());
  sim_hw::EmulatedV4l2Node depth, color;
  std::shared_ptr<FaultInjectingIo> io;
  drivers::CameraConfig config;
  std::uint64_t sequence = 0;

  Rig() {
    create_nodes();
    io = std::make_shared<FaultInjectingIo>(std::map<std::string, std::string>{
        {"/dev/video0", prefix + "_depth"}, {"/dev/video2", prefix + "_color"}});
    config.name = "cam_emulated";
    config.backend = "v4l2";
    config.uri = "depth=/dev/video0,color=/dev/video2";
    config.depth_mode = config.color_mode = {kW, kH, 30};
    config.depth_intrinsics = config.color_intrinsics = {kW, kH, 50.0, 50.0, 32.0, 24.0};
    config.read_timeout = std::chrono::milliseconds(100);
  }
  void create_nodes() {
    depth = sim_hw::EmulatedV4l2Node::create(prefix + "_depth", V4L2_PIX_FMT_Z16, kW, kH, 30);
    color = sim_hw::EmulatedV4l2Node::create(prefix + "_color", V4L2_PIX_FMT_YUYV, kW, kH, 30);
  }
  // Publishes frame `sequence` (depth and colour with one timestamp); returns its timestamp.
  std::int64_t publish() {
    ++sequence;
    const std::int64_t t = sim_hw::monotonic_us();
    const auto d = depth_pattern(sequence);
    depth.publish(reinterpret_cast<const std::uint8_t*>(d.data()), d.size() * 2, sequence, t);
    std::vector<std::uint8_t> yuyv;
    drivers::rgb_to_yuyv(rgb_pattern(sequence).data(), kW, kH, yuyv);
    color.publish(yuyv.data(), yuyv.size(), sequence, t);
    return t;
  }
};

}  // namespace

TEST_CASE("v4l2 back-end delivers the published depth exactly and colour within YUYV rounding", "[v4l2]") {
  Rig rig;
  drivers::V4l2D415Camera cam(rig.io);
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  for (int i = 0; i < 5; ++i) {
    const std::int64_t t = rig.publish();
    REQUIRE(cam.read(f) == drivers::ReadStatus::kFrame);
    CHECK(f.sequence == rig.sequence);
    CHECK(f.device_time_us == t);
    CHECK(f.depth_mm == depth_pattern(rig.sequence));
    REQUIRE(f.rgb.size() == static_cast<std::size_t>(kW * kH * 3));
    CHECK(f.color_intrinsics.width == kW);
    const auto expected = rgb_pattern(rig.sequence);
    int worst = 0;
    for (std::size_t j = 0; j < expected.size(); ++j) worst = std::max(worst, std::abs(f.rgb[j] - expected[j]));
    CHECK(worst <= 3);
  }
  CHECK(cam.health().frames == 5);
  CHECK(cam.health().state == drivers::CameraState::kActive);
  CHECK(cam.deactivate().ok);
  CHECK(rig.io->open_fds() == 0);
}

TEST_CASE("v4l2 format negotiation failures name the device, the ioctl and both formats", "[v4l2]") {
  Rig rig;
  drivers::CameraConfig c = rig.config;
  c.depth_mode = {1280, 720, 30};
  c.depth_intrinsics.width = 1280;
  c.depth_intrinsics.height = 720;
  drivers::V4l2D415Camera cam(rig.io);
  drivers::DriverResult r = cam.configure(c);
  CHECK_FALSE(r.ok);
  CHECK_THAT(r.message, Catch::Contains("cam_emulated: /dev/video0: VIDIOC_S_FMT: device offers Z16  64x48, "
                                        "configured Z16  1280x720"));
  c = rig.config;
  c.uri = "depth=/dev/video2";  // the colour node
  r = cam.configure(c);
  CHECK_THAT(r.message, Catch::Contains("/dev/video2: VIDIOC_S_FMT: device offers YUYV 64x48"));
  c.uri = "depth=/dev/video7";
  CHECK_THAT(cam.configure(c).message, Catch::Contains("/dev/video7: open: No such file or directory"));
  c.uri = "depth=/dev/video0,colour=/dev/video2";
  CHECK_THAT(cam.configure(c).message, Catch::Contains("expected depth=/dev/videoN[,color=/dev/videoM]"));
  rig.io->faults[VIDIOC_REQBUFS] = {ENOMEM};
  CHECK_THAT(cam.configure(rig.config).message, Catch::Contains("/dev/video0: VIDIOC_REQBUFS: Cannot allocate memory"));
  c = rig.config;
  c.depth_intrinsics = drivers::Intrinsics{};  // the config file left them out
  CHECK_THAT(cam.configure(c).message, Catch::Contains("cam_emulated: depth_intrinsics are missing"));
  CHECK(rig.io->open_fds() == 0);  // nothing left open after failures
}

TEST_CASE("v4l2 DQBUF retries EINTR and times out when no frame comes", "[v4l2]") {
  Rig rig;
  drivers::V4l2D415Camera cam(rig.io);
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  rig.io->faults[VIDIOC_DQBUF] = {EINTR, EINTR};
  rig.publish();
  const int before = rig.io->calls[VIDIOC_DQBUF];
  CHECK(cam.read(f) == drivers::ReadStatus::kFrame);
  CHECK(rig.io->calls[VIDIOC_DQBUF] >= before + 3);
  const auto start = std::chrono::steady_clock::now();
  CHECK(cam.read(f) == drivers::ReadStatus::kTimeout);
  // It waited its 100 ms read timeout (that it also returns soon after is the [real_time] case
  // below: an upper bound on the wall clock has no place in a sanitizer run).
  CHECK(std::chrono::steady_clock::now() - start >= std::chrono::milliseconds(95));
  CHECK(cam.health().timeouts == 1);
  // A frame that waited 600 ms (> stale_after 500 ms) somewhere before the read is stale.
  const auto d = depth_pattern(7);
  rig.depth.publish(reinterpret_cast<const std::uint8_t*>(d.data()), d.size() * 2, 7, sim_hw::monotonic_us() - 600'000);
  CHECK(cam.read(f) == drivers::ReadStatus::kStale);
  CHECK(f.depth_mm == d);  // a stale frame is still returned
  CHECK(cam.health().stale == 1);
}

TEST_CASE("v4l2 read without a frame returns within 10x its 100 ms read timeout", "[v4l2][real_time]") {
  Rig rig;
  drivers::V4l2D415Camera cam(rig.io);
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  const auto start = std::chrono::steady_clock::now();
  CHECK(cam.read(f) == drivers::ReadStatus::kTimeout);
  const auto waited = std::chrono::steady_clock::now() - start;
  CHECK(waited >= std::chrono::milliseconds(95));
  // Not a read that blocks (forever, or for a whole second timeout per retry): 10x the timeout,
  // so that a busy machine, which may wake the reader late, does not fail it.
  CHECK(waited < std::chrono::milliseconds(1000));
}

TEST_CASE("v4l2 device loss gives kLost, then reopens when the device is back", "[v4l2]") {
  Rig rig;
  drivers::V4l2D415Camera cam(rig.io);
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  rig.publish();
  REQUIRE(cam.read(f) == drivers::ReadStatus::kFrame);

  rig.depth.mark_dead();  // unplugged
  CHECK(cam.read(f) == drivers::ReadStatus::kLost);
  drivers::CameraHealth h = cam.health();
  CHECK(h.state == drivers::CameraState::kLost);
  CHECK_THAT(h.message, Catch::Contains("/dev/video0: VIDIOC_DQBUF: No such device"));
  CHECK(cam.read(f) == drivers::ReadStatus::kLost);  // immediate reopen attempt fails: still dead
  CHECK(cam.health().reopen_attempts == 1);
  CHECK_THAT(cam.health().message, Catch::Contains("reopen attempt 1 failed"));

  rig.create_nodes();  // plugged back in
  drivers::ReadStatus s = drivers::ReadStatus::kLost;
  // The first reopen is due 100 ms after the failed one (the backoff); 30 s only keeps a camera
  // that never reopens from hanging the test.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (s != drivers::ReadStatus::kFrame && std::chrono::steady_clock::now() < give_up) {
    rig.publish();
    s = cam.read(f);
    if (s == drivers::ReadStatus::kLost) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(s == drivers::ReadStatus::kFrame);
  h = cam.health();
  INFO(h.message);
  CHECK(h.reopened == 1);
  CHECK(h.reopen_attempts >= 2);
  CHECK(h.state == drivers::CameraState::kActive);

  rig.io->faults[VIDIOC_DQBUF] = {EIO};  // an I/O error also means reopen
  CHECK(cam.read(f) == drivers::ReadStatus::kLost);
  rig.publish();
  CHECK(cam.read(f) == drivers::ReadStatus::kTimeout);  // reopened at once; frames from now on
  rig.publish();
  CHECK(cam.read(f) == drivers::ReadStatus::kFrame);
  CHECK(cam.health().reopened == 2);
}

TEST_CASE("v4l2 short frame is rejected as corrupt by the monitor", "[v4l2]") {
  Rig rig;
  drivers::MonitoredDepthCamera cam(std::make_unique<drivers::V4l2D415Camera>(rig.io));
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  drivers::DepthFrame f;
  rig.publish();
  CHECK(cam.read(f) == drivers::ReadStatus::kFrame);
  const auto d = depth_pattern(99);
  rig.depth.publish(reinterpret_cast<const std::uint8_t*>(d.data()), d.size(), ++rig.sequence, sim_hw::monotonic_us());
  CHECK(cam.read(f) == drivers::ReadStatus::kCorrupt);
  CHECK_THAT(cam.health().message, Catch::Contains("depth image has 1536 pixels, intrinsics say 64x48 = 3072"));
}

TEST_CASE("v4l2 colour is paired with the depth frame nearest in time", "[v4l2]") {
  Rig rig;
  drivers::V4l2D415Camera cam(rig.io);
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  auto put_depth = [&](std::uint64_t k, std::int64_t t) {
    const auto d = depth_pattern(k);
    rig.depth.publish(reinterpret_cast<const std::uint8_t*>(d.data()), d.size() * 2, k, t);
  };
  auto put_color = [&](std::uint64_t k, std::int64_t t) {
    std::vector<std::uint8_t> yuyv;
    drivers::rgb_to_yuyv(rgb_pattern(k).data(), kW, kH, yuyv);
    rig.color.publish(yuyv.data(), yuyv.size(), k, t);
  };
  auto colour_is = [](const drivers::DepthFrame& f, std::uint64_t k) {
    const auto expected = rgb_pattern(k);
    if (f.rgb.size() != expected.size()) return false;
    for (std::size_t j = 0; j < expected.size(); ++j)
      if (std::abs(f.rgb[j] - expected[j]) > 3) return false;
    return true;
  };
  const std::int64_t t0 = sim_hw::monotonic_us();
  put_color(101, t0 - 20'000);  // colour runs 2 ms ahead of depth, one frame is old
  put_color(102, t0 + 2'000);
  put_color(103, t0 + 35'333);  // already the next depth frame's partner
  put_depth(1, t0);
  drivers::DepthFrame f;
  REQUIRE(cam.read(f) == drivers::ReadStatus::kFrame);
  CHECK(colour_is(f, 102));
  put_depth(2, t0 + 33'333);
  REQUIRE(cam.read(f) == drivers::ReadStatus::kFrame);
  CHECK(colour_is(f, 103));  // carried over from the previous read
  put_depth(3, t0 + 66'666);  // its colour never comes: the frame goes out without colour
  REQUIRE(cam.read(f) == drivers::ReadStatus::kFrame);
  CHECK(f.rgb.empty());
  CHECK(f.color_intrinsics.width == 0);
  CHECK(f.depth_mm == depth_pattern(3));
}

TEST_CASE("v4l2 back-end flags a buffer whose timestamp no clock gives as corrupt", "[v4l2]") {
  // Found by fuzzing (tests/fuzz v4l2_frames): tv_sec * 1000000 overflowed (undefined behaviour).
  Rig rig;
  drivers::V4l2D415Camera cam(rig.io);
  REQUIRE(cam.configure(rig.config).ok);
  REQUIRE(cam.activate().ok);
  rig.io->on_dqbuf = [](v4l2_buffer& b) { b.timestamp.tv_sec = std::numeric_limits<decltype(b.timestamp.tv_sec)>::min(); };
  rig.publish();
  drivers::DepthFrame frame;
  CHECK(cam.read(frame) == drivers::ReadStatus::kCorrupt);
  rig.io->on_dqbuf = [](v4l2_buffer& b) { b.timestamp.tv_usec = 5'000'000; };
  rig.publish();
  CHECK(cam.read(frame) == drivers::ReadStatus::kCorrupt);
  rig.io->on_dqbuf = nullptr;
  rig.publish();
  CHECK(cam.read(frame) == drivers::ReadStatus::kFrame);
}
