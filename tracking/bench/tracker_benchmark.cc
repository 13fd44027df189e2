// Tracker benchmark (a program that prints figures, not a test): three depth frames of a
// sagging sheet -> tracked surface on a ~6000-triangle mesh, median and 99th percentile
// milliseconds per cycle and per stage, at each requested resolution. The frames come from the
// analytic ray caster of the tracker tests (tests/tracking/analytic_scene.h), with D415 noise.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "tests/tracking/analytic_scene.h"
#include "tracking/cloud_surface.h"
#include "tracking/sheet_tracker.h"

namespace {

using tracking::testing::SheetShape;

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
  return v[k];
}

// CPU time of the whole process (all threads), ms: wall time on a shared machine includes time
// other processes took from us; CPU time does not.
double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * t.tv_sec + 1e-6 * t.tv_nsec;
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one;
  in >> one;
  return one.empty() ? "?" : one;
}

struct Resolution {
  int width, height;
};

Resolution parse_resolution(const std::string& text) {
  Resolution r{0, 0};
  if (std::sscanf(text.c_str(), "%dx%d", &r.width, &r.height) != 2 || r.width <= 0 ||
      r.height <= 0) {
    throw CLI::ValidationError("--resolutions", "expected WIDTHxHEIGHT, got '" + text + "'");
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Sheet tracker benchmark: three depth frames -> tracked surface"};
  std::vector<std::string> resolutions{"848x480", "1280x720"};
  int cycles = 60, cols = 61, rows = 51;
  int stride = tracking::FusionOptions{}.pixel_stride;
  double voxel_m = tracking::ResampleOptions{}.voxel_m;
  int calibration_every = tracking::CalibrationCheckOptions{}.every_n_cycles;
  app.add_option("--resolutions", resolutions, "depth resolutions, WIDTHxHEIGHT")->delimiter(',');
  app.add_option("--cycles", cycles, "tracker cycles per resolution")->check(CLI::PositiveNumber);
  app.add_option("--cols", cols, "mesh vertices along 1.17 m")->check(CLI::Range(2, 1000));
  app.add_option("--rows", rows, "mesh vertices along 0.975 m")->check(CLI::Range(2, 1000));
  app.add_option("--stride", stride, "pixel stride of the fusion")->check(CLI::Range(1, 8));
  int iterations = tracking::RegistrationOptions{}.max_iterations;
  app.add_option("--iterations", iterations, "registration Gauss-Newton iterations at most")
      ->check(CLI::PositiveNumber);
  bool cold = false;
  app.add_flag("--cold", cold,
               "every cycle's registration starts from the prediction (registration.warm_start "
               "off), as a cell's first cycle does");
  bool approximate_voxels = false;
  app.add_flag("--approximate-voxels", approximate_voxels,
               "pcl::ApproximateVoxelGrid instead of pcl::VoxelGrid");
  app.add_option("--voxel-m", voxel_m, "voxel size (m)")->check(CLI::PositiveNumber);
  app.add_option("--calibration-every", calibration_every,
                 "run the calibration check every N cycles (0 = never)")
      ->check(CLI::NonNegativeNumber);
  std::string ply_dir;
  app.add_option("--ply", ply_dir,
                 "write the last cycle's tracked surface and the PCL reconstruction of its cloud "
                 "to DIR/tracked_<res>.ply and DIR/cloud_surface_<res>.ply");
  CLI11_PARSE(app, argc, argv);

  SheetShape truth;
  truth.slope_x = 0.04;
  truth.ripple_m = 0.015;
  SheetShape predicted;
  predicted.sag_m = 0.085;
  std::shared_ptr<const tracking::testing::SaggingSheet> sheet;
  const tracking::testing::Scene scene = tracking::testing::sheet_scene(truth, &sheet);
  const tracking::SurfaceMesh prediction =
      tracking::testing::SaggingSheet(predicted, {0, 0, 0}).mesh(cols, rows);
  fmt::print(
      "mesh: {} vertices, {} triangles; {} cycles per resolution; pixel stride {}, voxel "
      "{} m, calibration check every {} cycles; load average {}\n",
      prediction.vertices_m.size(), prediction.triangles.size(), cycles, stride, voxel_m,
      calibration_every, load_average());

  for (const std::string& text : resolutions) {
    const Resolution res = parse_resolution(text);
    // Two frame sets with different noise, alternated, so no cycle sees the previous one's input.
    std::vector<std::vector<drivers::DepthFrame>> sets(2);
    const auto cameras = tracking::testing::three_cameras(res.width, res.height);
    for (std::size_t s = 0; s < sets.size(); ++s) {
      for (std::size_t c = 0; c < cameras.size(); ++c) {
        sets[s].push_back(tracking::testing::render_frame(
            scene, cameras[c], {0.0015, static_cast<std::uint32_t>(100 * s + c + 1)}));
      }
    }
    tracking::TrackerConfig config;
    config.segmentation.box_min_m = tracking::Vec3(-0.9, -0.8, 0.5);
    config.segmentation.box_max_m = tracking::Vec3(0.9, 0.8, 1.3);
    config.fusion.pixel_stride = stride;
    config.resample.voxel_m = voxel_m;
    config.resample.approximate = approximate_voxels;
    config.registration.max_iterations = iterations;
    config.registration.warm_start = !cold;
    config.calibration.enabled = calibration_every > 0;
    config.calibration.every_n_cycles = std::max(calibration_every, 1);
    tracking::SheetTracker tracker(config);
    tracker.track(sets[0], prediction);  // warm-up: ray tables, symbolic analysis
    std::vector<double> cpu, total, fusion, seg, resample, reg, cov, err, cal, mean_err, max_err;
    std::vector<double> reg_iterations;
    int warm_cycles = 0, restarts = 0;
    for (int k = 0; k < cycles; ++k) {
      const double cpu_before = cpu_ms();
      const tracking::TrackResult r = tracker.track(sets[k % 2], prediction);
      cpu.push_back(cpu_ms() - cpu_before);
      if (r.status != tracking::TrackStatus::kOk) {
        fmt::print(stderr, "cycle {}: {} ({})\n", k, tracking::to_string(r.status), r.message);
        return 1;
      }
      warm_cycles += r.registration_warm;
      restarts += r.registration_restarted;
      reg_iterations.push_back(r.registration_iterations);
      total.push_back(r.times.total_ms);
      fusion.push_back(r.times.fusion_ms);
      seg.push_back(r.times.segmentation_ms);
      resample.push_back(r.times.resample_ms);
      reg.push_back(r.times.registration_ms);
      cov.push_back(r.times.coverage_ms);
      err.push_back(r.times.prediction_error_ms);
      cal.push_back(r.times.calibration_ms);
      double sum = 0, worst = 0;
      for (const tracking::Vec3& v : r.vertices_m) {
        const double d = sheet->distance(v);
        sum += d;
        worst = std::max(worst, d);
      }
      mean_err.push_back(sum / r.vertices_m.size());
      max_err.push_back(worst);
    }
    const auto line = [&](const char* stage, const std::vector<double>& ms) {
      fmt::print("figure: {} stage={:<16} median_ms={:7.2f} p99_ms={:7.2f}\n", text, stage,
                 percentile(ms, 0.5), percentile(ms, 0.99));
    };
    line("cycle", total);
    line("cycle_cpu_time", cpu);  // both cores' CPU time: shows contention when above wall time
    line("fusion", fusion);
    line("segmentation", seg);
    line("resample+index", resample);
    line("registration", reg);
    line("coverage", cov);
    line("prediction_error", err);
    line("calibration", cal);
    fmt::print("figure: {} registration: {} of {} cycles warm, {} restarted from the prediction, "
               "median {} iterations\n",
               text, warm_cycles, cycles, restarts, percentile(reg_iterations, 0.5));
    fmt::print(
        "figure: {} tracked-surface error vs truth: mean {:.2f} mm (median cycle {:.2f} mm), max {:.2f} mm (worst cycle)\n",
        text, 1e3 * *std::max_element(mean_err.begin(), mean_err.end()), 1e3 * percentile(mean_err, 0.5),
        1e3 * *std::max_element(max_err.begin(), max_err.end()));
    fmt::print("load average after {}: {}\n", text, load_average());
    if (!ply_dir.empty()) {
      const tracking::TrackResult r = tracker.track(sets[0], prediction);
      tracking::SurfaceMesh tracked = prediction;
      tracked.vertices_m = r.vertices_m;
      const auto start = std::chrono::steady_clock::now();
      const tracking::SurfaceMesh display =
          tracking::reconstruct_surface(tracker.last_resampled_cloud(), {});
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      try {
        tracking::write_ply(fmt::format("{}/tracked_{}.ply", ply_dir, text), tracked);
        tracking::write_ply(fmt::format("{}/cloud_surface_{}.ply", ply_dir, text), display);
      } catch (const std::exception& e) {
        fmt::print(stderr, "{}\n", e.what());
        return 1;
      }
      fmt::print("display reconstruction {}: {} triangles from {} points in {:.1f} ms\n", text,
                 display.triangles.size(), tracker.last_resampled_cloud().size(), ms);
    }
  }
  return 0;
}
