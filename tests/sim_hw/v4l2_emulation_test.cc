// The real V4L2 back-end in a separate process (the real camera_probe tool) reading emulated
// /dev/video nodes through the LD_PRELOAD shim, while this test publishes frames into the nodes'
// shared memory, unplugs the depth node and plugs it back in.

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <linux/videodev2.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "drivers/pnm_image.h"
#include "drivers/yuyv_color.h"
#include "sim_hw/emulated_v4l2_node.h"
#include "tests/support/temp_dir.h"

extern char** environ;

namespace {

constexpr int kW = 64, kH = 48;
namespace fs = std::filesystem;

std::vector<std::uint16_t> depth_pattern(std::uint64_t k) {
  std::vector<std::uint16_t> d(kW * kH);
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = static_cast<std::uint16_t>(300 + (i * 11 + k * 17) % 4000);
  return d;
}

std::vector<std::uint8_t> rgb_pattern(std::uint64_t k) {  // pixel pairs share a colour
  std::vector<std::uint8_t> rgb(kW * kH * 3);
  for (std::size_t p = 0; p < static_cast<std::size_t>(kW * kH); ++p)
    for (int c = 0; c < 3; ++c) rgb[3 * p + c] = static_cast<std::uint8_t>(20 + ((p / 2) * (3 + c) + k * (c + 1)) % 200);
  return rgb;
}

std::string config_json(const std::string& uri) {
  return R"({"cameras": [{"name": "cam0", "backend": "v4l2", "uri": ")" + uri + R"(",
    "depth_mode": {"width": 64, "height": 48, "fps": 30}, "color_mode": {"width": 64, "height": 48, "fps": 30},
    "depth_intrinsics": {"width": 64, "height": 48, "fx": 50, "fy": 50, "cx": 32, "cy": 24},
    "color_intrinsics": {"width": 64, "height": 48, "fx": 50, "fy": 50, "cx": 32, "cy": 24},
    "camera_to_cell": {"translation_m": [0, 0, 1.5], "rpy_deg": [180, 0, 0]}}]})";
}

// Starts `exe` with the shim preloaded and PREPREG_V4L2_EMULATION=`emulation`, stdout and
// stderr into `out_file`.
pid_t spawn_with_shim(const std::string& exe, const std::vector<std::string>& args, const std::string& emulation,
                      const fs::path& out_file) {
  std::vector<std::string> env_text = {std::string("LD_PRELOAD=") + V4L2_SHIM_SO,
                                       "PREPREG_V4L2_EMULATION=" + emulation};
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("LD_PRELOAD=", 0) != 0 && std::string(*e).rfind("PREPREG_V4L2", 0) != 0) env_text.push_back(*e);
  std::vector<char*> envp, argv;
  for (auto& s : env_text) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> all = {exe};
  all.insert(all.end(), args.begin(), args.end());
  for (auto& s : all) argv.push_back(s.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(spawned == 0);
  return pid;
}

// Waits for the child; returns its exit status (-1 if killed), its output in `output`.
int wait_for(pid_t pid, const fs::path& out_file, std::string& output) {
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  std::ifstream in(out_file);
  std::stringstream text;
  text << in.rdbuf();
  output = text.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int run_probe(const std::vector<std::string>& args, const std::string& emulation, const fs::path& out_file,
              std::string& output) {
  return wait_for(spawn_with_shim(CAMERA_PROBE_EXE, args, emulation, out_file), out_file, output);
}

// Compares every frame camera_probe dumped with what was published under its sequence number:
// depth exactly, colour within `color_tolerance` levels. Returns how many frames it checked.
int check_dumped_frames(const fs::path& dump, int color_tolerance) {
  int checked = 0;
  for (const auto& e : fs::directory_iterator(dump)) {
    const std::string name = e.path().filename().string();
    if (!name.ends_with("_depth.pgm")) continue;
    const std::uint64_t seq = std::stoull(name.substr(5, name.size() - 5 - 10));  // cam0_<seq>_depth.pgm
    const std::vector<std::uint16_t> got = drivers::read_pgm16(e.path(), kW, kH);
    CHECK(got == depth_pattern(seq));  // exact
    const fs::path color_file = dump / ("cam0_" + std::to_string(seq) + "_color.ppm");
    REQUIRE(fs::exists(color_file));
    const auto rgb = drivers::read_ppm8(color_file, kW, kH);
    const auto expected = rgb_pattern(seq);
    REQUIRE(rgb.size() == expected.size());
    int worst = 0;
    for (std::size_t i = 0; i < rgb.size(); ++i) worst = std::max(worst, std::abs(rgb[i] - expected[i]));
    CHECK(worst <= color_tolerance);  // YUYV (BT.601, 8 bit) rounding
    ++checked;
  }
  return checked;
}

// The emulator's nodes exist once it has opened its camera (gives up after 10 s or when the
// emulator `pid` has exited).
void wait_for_node(const std::string& name, pid_t pid) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < give_up) {
    siginfo_t info{};
    if (waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid)
      return;  // exited (not reaped here: wait_for() collects it)
    const int fd = shm_open(("/" + name).c_str(), O_RDONLY, 0);
    if (fd >= 0) {
      ::close(fd);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

int depth_files(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().string().ends_with("_depth.pgm");
  return n;
}

}  // namespace

TEST_CASE("camera_probe reads emulated V4L2 nodes through the LD_PRELOAD shim, survives an unplug",
          "[v4l2_emulation]") {
  testing_support::TempDir dir("v4l2_emulation");
  fs::create_directories(dir / "dump");
  testing_support::write_file(dir / "cell.json", config_json("depth=/dev/video0,color=/dev/video2"));
  const std::string prefix = "prepreg_emutest_" + std::to_string(::getpid());
  sim_hw::EmulatedV4l2Node depth = sim_hw::EmulatedV4l2Node::create(prefix + "_depth", V4L2_PIX_FMT_Z16, kW, kH, 30);
  sim_hw::EmulatedV4l2Node color = sim_hw::EmulatedV4l2Node::create(prefix + "_color", V4L2_PIX_FMT_YUYV, kW, kH, 30);

  std::atomic<bool> stop{false};
  std::uint64_t sequence = 0;
  bool unplugged = false;
  // The producer: 30 fps; once the probe has written 5 frames (however long a busy machine takes
  // to start it), unplug the depth node for 300 ms and plug a fresh one in under the same name
  // (the probe must reopen it).
  auto producer = [&] {
    std::vector<std::uint8_t> yuyv;
    auto next = std::chrono::steady_clock::now();
    while (!stop) {
      if (!unplugged && depth_files(dir / "dump") >= 5) {
        depth.mark_dead();
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        depth = sim_hw::EmulatedV4l2Node::create(prefix + "_depth", V4L2_PIX_FMT_Z16, kW, kH, 30);
        unplugged = true;
      }
      ++sequence;
      const std::int64_t t = sim_hw::monotonic_us();
      const auto d = depth_pattern(sequence);
      depth.publish(reinterpret_cast<const std::uint8_t*>(d.data()), d.size() * 2, sequence, t);
      drivers::rgb_to_yuyv(rgb_pattern(sequence).data(), kW, kH, yuyv);
      color.publish(yuyv.data(), yuyv.size(), sequence, t);
      next += std::chrono::microseconds(33'333);
      std::this_thread::sleep_until(next);
    }
  };
  std::thread producer_thread(producer);
  std::string output;
  // 40 frames at 30 fps and the unplug take about 2 s; 30 s is the probe's limit only so that
  // one that never gets its frames ends.
  const int status = run_probe({"--config", (dir / "cell.json").string(), "--frames", "40", "--max-seconds", "30",
                                "--dump", (dir / "dump").string()},
                               "/dev/video0=" + prefix + "_depth,/dev/video2=" + prefix + "_color",
                               dir / "probe.txt", output);
  stop = true;
  producer_thread.join();
  INFO(output);
  CHECK(status == 0);
  CHECK(unplugged);
  std::smatch m;
  REQUIRE(std::regex_search(output, m, std::regex(R"(summary camera=cam0 frames=(\d+) .* lost=(\d+) dropped=\d+ reopened=(\d+) state=(\w+))")));
  CHECK(std::stoi(m[1]) == 40);
  CHECK(std::stoi(m[2]) >= 1);
  CHECK(std::stoi(m[3]) == 1);
  CHECK(m[4] == "active");

  CHECK(check_dumped_frames(dir / "dump", 3) == 40);
}

TEST_CASE("the shim passes other paths through: a missing device is reported by path", "[v4l2_emulation]") {
  testing_support::TempDir dir("v4l2_emulation");
  testing_support::write_file(dir / "cell.json", config_json("depth=/dev/video9"));
  std::string output;
  const int status = run_probe({"--config", (dir / "cell.json").string(), "--frames", "2", "--max-seconds", "1"},
                               "/dev/video0=prepreg_nonexistent_depth", dir / "probe.txt", output);
  INFO(output);
  CHECK(status == 2);
  CHECK_THAT(output, Catch::Contains("/dev/video9: open: No such file or directory"));
  // An emulated path whose node does not exist fails like an absent device.
  testing_support::write_file(dir / "cell.json", config_json("depth=/dev/video0"));
  run_probe({"--config", (dir / "cell.json").string(), "--frames", "2", "--max-seconds", "1"},
            "/dev/video0=prepreg_nonexistent_depth", dir / "probe.txt", output);
  CHECK_THAT(output, Catch::Contains("/dev/video0: open: No such file or directory"));
}

TEST_CASE("d415_v4l2_emulator serves a camera to camera_probe through the shim", "[v4l2_emulation]") {
  // Source: nodes this test publishes into, read by the emulator's own V4L2 back-end (through the
  // shim); the emulator serves them again as fresh nodes, which camera_probe reads (through the
  // shim): two V4L2 hops, two YUYV round trips.
  testing_support::TempDir dir("v4l2_emulator");
  fs::create_directories(dir / "dump");
  testing_support::write_file(dir / "source.json", config_json("depth=/dev/video0,color=/dev/video2"));
  testing_support::write_file(dir / "probe.json", config_json("depth=/dev/video4,color=/dev/video6"));
  const std::string src = "prepreg_chain_" + std::to_string(::getpid()) + "_src";
  const std::string out = "prepreg_chain_" + std::to_string(::getpid()) + "_out";
  sim_hw::EmulatedV4l2Node depth = sim_hw::EmulatedV4l2Node::create(src + "_depth", V4L2_PIX_FMT_Z16, kW, kH, 30);
  sim_hw::EmulatedV4l2Node color = sim_hw::EmulatedV4l2Node::create(src + "_color", V4L2_PIX_FMT_YUYV, kW, kH, 30);
  std::atomic<bool> stop{false};
  std::thread producer([&] {
    std::vector<std::uint8_t> yuyv;
    auto next = std::chrono::steady_clock::now();
    for (std::uint64_t k = 1; !stop; ++k) {
      const std::int64_t t = sim_hw::monotonic_us();
      const auto d = depth_pattern(k);
      depth.publish(reinterpret_cast<const std::uint8_t*>(d.data()), d.size() * 2, k, t);
      drivers::rgb_to_yuyv(rgb_pattern(k).data(), kW, kH, yuyv);
      color.publish(yuyv.data(), yuyv.size(), k, t);
      next += std::chrono::microseconds(33'333);
      std::this_thread::sleep_until(next);
    }
  });
  const pid_t emulator = spawn_with_shim(
      D415_V4L2_EMULATOR_EXE,
      {"--config", (dir / "source.json").string(), "--camera", "cam0", "--prefix", out, "--depth-device",
       "/dev/video4", "--color-device", "/dev/video6", "--seconds", "120"},
      "/dev/video0=" + src + "_depth,/dev/video2=" + src + "_color", dir / "emulator.txt");
  wait_for_node(out + "_color", emulator);
  std::string probe_output, emulator_output;
  // 20 frames at 30 fps take under a second; the limits (the probe's 60 s, the emulator's 120 s,
  // which is stopped once the probe is done) only end a run that gets no frames.
  const int status = run_probe({"--config", (dir / "probe.json").string(), "--frames", "20", "--max-seconds", "60",
                                "--dump", (dir / "dump").string()},
                               "/dev/video4=" + out + "_depth,/dev/video6=" + out + "_color", dir / "probe.txt",
                               probe_output);
  ::kill(emulator, SIGTERM);
  const int emulator_status = wait_for(emulator, dir / "emulator.txt", emulator_output);
  stop = true;
  producer.join();
  INFO(probe_output);
  INFO(emulator_output);
  CHECK(status == 0);
  CHECK(emulator_status == 0);
  CHECK_THAT(emulator_output, Catch::Contains("emulation /dev/video4=" + out + "_depth,/dev/video6=" + out + "_color"));
  CHECK_THAT(emulator_output, Catch::Contains("uri depth=/dev/video4,color=/dev/video6"));
  CHECK(check_dumped_frames(dir / "dump", 6) == 20);
}

TEST_CASE("a simulated D415 through the V4L2 emulation: its faults reach camera_probe", "[v4l2_emulation]") {
  // The issue's CI path: simulated D415 (sim_hw) -> d415_v4l2_emulator -> shm nodes -> shim ->
  // the real V4L2 back-end and frame monitor in camera_probe. The scene dies, freezes and stalls
  // its clock for 0.6 s each.
  testing_support::TempDir dir("v4l2_simulated");
  nlohmann::json scene = nlohmann::json::parse(
      std::ifstream(std::string(PREPREG_SOURCE_DIR) + "/sim_hw/scenes/d415_table_scene.json"));
  // Wall clock: frames carry real capture times, as a device's do (a simulated clock would run
  // slower than real time whenever rendering falls behind, and its frames would look stale).
  scene["clock"] = "wall";
  scene["faults"] = {{"dead_from_s", 1.0}, {"dead_until_s", 1.6}, {"frozen_from_s", 2.2}, {"frozen_until_s", 2.8},
                     {"stale_from_s", 3.4}, {"stale_until_s", 4.0}, {"stale_mode", "stopped"}};
  testing_support::write_file(dir / "scene.json", scene.dump());
  const std::string camera = R"({"cameras": [{"name": "cam_front", "backend": "BACKEND", "uri": "URI",
    "depth_mode": {"width": 848, "height": 480, "fps": 30}, "color_mode": {"width": 848, "height": 480, "fps": 30},
    "depth_intrinsics": {"width": 848, "height": 480, "fx": 665.6, "fy": 665.6, "cx": 424, "cy": 240},
    "color_intrinsics": {"width": 848, "height": 480, "fx": 617, "fy": 617, "cx": 424, "cy": 240},
    "depth_to_color": {"translation_m": [0.015, 0, 0], "quaternion_wxyz": [1, 0, 0, 0]},
    "camera_to_cell": {"translation_m": [0, -1.5, 1.25], "rpy_deg": [-90, 0, 0]}}]})";
  auto config = [&](const std::string& backend, const std::string& uri) {
    std::string text = camera;
    text.replace(text.find("BACKEND"), 7, backend);
    text.replace(text.find("URI"), 3, uri);
    return text;
  };
  testing_support::write_file(dir / "sim.json", config("simulated", (dir / "scene.json").string()));
  testing_support::write_file(dir / "v4l2.json", config("v4l2", "depth=/dev/video0,color=/dev/video2"));
  const std::string prefix = "prepreg_simd415_" + std::to_string(::getpid());
  const pid_t emulator = spawn_with_shim(
      D415_V4L2_EMULATOR_EXE,
      {"--config", (dir / "sim.json").string(), "--camera", "cam_front", "--prefix", prefix, "--seconds", "120"}, "",
      dir / "emulator.txt");
  wait_for_node(prefix + "_color", emulator);
  std::string output, emulator_output;
  // 100 frames take 3.3 s at 30 fps, more where rendering falls behind; the limits (the probe's
  // 60 s, the emulator's 120 s, which is stopped once the probe is done) only end a stuck run.
  const int status = run_probe({"--config", (dir / "v4l2.json").string(), "--frames", "100", "--max-seconds", "60"},
                               "/dev/video0=" + prefix + "_depth,/dev/video2=" + prefix + "_color",
                               dir / "probe.txt", output);
  ::kill(emulator, SIGTERM);
  wait_for(emulator, dir / "emulator.txt", emulator_output);
  INFO(output);
  INFO(emulator_output);
  CHECK(status == 0);
  std::smatch m;
  REQUIRE(std::regex_search(output, m, std::regex(R"(summary camera=cam_front frames=(\d+) fps=[\d.]+ valid=([\d.]+) .* stale=(\d+) frozen=(\d+) corrupt=(\d+) lost=(\d+) dropped=\d+ reopened=(\d+) state=(\w+))")));
  CHECK(std::stoi(m[1]) == 100);
  CHECK(std::stod(m[2]) > 20.0);  // the sheet, table and floor are in view
  // 0.6 s of a stopped clock and 0.6 s frozen: flagged from the first or second repeat on (fewer
  // frames when a loaded machine renders below 30 fps).
  CHECK(std::stoi(m[3]) >= 2);
  CHECK(std::stoi(m[4]) >= 2);
  CHECK(std::stoi(m[5]) == 0);
  CHECK(std::stoi(m[6]) >= 1);  // the dead camera was lost ...
  CHECK(std::stoi(m[7]) == 1);  // ... and reopened once it came back
  CHECK(m[8] == "active");
}
