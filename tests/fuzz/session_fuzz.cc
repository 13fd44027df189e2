// Recorded camera sessions (drivers/camera_session.h: session.json, each camera's index.txt and its
// PGM/PPM frames), replayed by the "replay" camera back-end (drivers/replay_camera.h) as the cell,
// the tracker benchmark and CI replay them. The first byte chooses the replay options (always
// pace=fast: a paced replay only adds waiting); the rest holds the session's files (fuzz_support.h:
// "%%FILE name" lines), session.json first.
#include "drivers/replay_camera.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t options = data[0];
  fuzz::write_scratch_files(data + 1, size - 1, "session.json");
  const std::string dir = fuzz::scratch_dir().string();

  drivers::CameraConfig config;
  config.name = "cam";
  config.backend = "replay";
  config.uri = dir + "#cam?pace=fast";
  if (options & 1) config.uri += "&loop=1";
  if (options & 2) config.uri += "&live=1";
  if (options & 4) config.uri += "&rebase=1";
  config.read_timeout = std::chrono::milliseconds(0);

  drivers::ReplayDepthCamera camera;
  const drivers::DriverResult configured = camera.configure(config);
  if (!configured.ok) {
    fuzz::require_named(std::runtime_error(configured.message), dir);
    return 0;
  }
  if (!camera.activate().ok) std::abort();  // a configured replay always activates
  drivers::DepthFrame frame;
  // More reads than frames, so that the end of the recording (or a loop) is reached.
  const std::size_t reads = std::min<std::size_t>(2 * camera.recorded_frames() + 2, 16);
  for (std::size_t i = 0; i < reads; ++i) {
    const drivers::ReadStatus status = camera.read(frame);
    if (status == drivers::ReadStatus::kFrame) {
      const std::size_t pixels = static_cast<std::size_t>(frame.depth_intrinsics.width) *
                                 static_cast<std::size_t>(frame.depth_intrinsics.height);
      if (frame.depth_mm.size() != pixels) std::abort();  // a frame of another size than it says
    }
    const drivers::CameraHealth health = camera.health();
    if (health.state == drivers::CameraState::kDegraded && health.message.find("corrupt") != std::string::npos) {
      fuzz::require_named(std::runtime_error(health.message), dir);
    }
  }
  camera.deactivate();
  return 0;
}
