// `extract_markers`: raw scanner points -> one position per manifest marker.
//   extract_markers --scan SCAN.xyz --guide GUIDE.xyz --out MARKERS.xyz
//                   [--marker-radius-m R] [--viewpoint X Y Z] [--gate-m G]
//                   [--cluster-tolerance-m T] [--min-points N] [--max-points N]
// GUIDE has one approximate position per manifest marker, in manifest order ("nan nan nan" for
// no guess); MARKERS gets one line per manifest marker in the same order, "nan nan nan" for a
// marker not found. Scan model and method: tracking/marker_extraction.h.
// Exit status: 0 success; 2 bad input (command line, unreadable or malformed file, file:line in
// the message); 1 the output could not be written.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "tracking/marker_extraction.h"
#include "tracking/xyz_io.h"

namespace {

using namespace tracking;

constexpr int kBadInput = 2;
constexpr int kWriteFailed = 1;

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

int run(const std::string& scan_path, const std::string& guide_path, const std::string& out_path,
        const MarkerExtractionOptions& options) {
  std::vector<Vec3> scan, guide;
  MarkerExtractionReport report;
  std::vector<MarkerCandidate> candidates;
  MarkerMatch match;
  try {
    scan = read_xyz_file(scan_path, /*allow_nan=*/false);
    guide = read_xyz_file(guide_path, /*allow_nan=*/true);
    if (guide.empty()) throw std::invalid_argument(guide_path + ": no markers in the guide");
    candidates = extract_marker_candidates(scan, options, &report);
    match = match_markers_to_manifest(candidates, guide, options.gate_m);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "extract_markers: %s\n", e.what());
    return kBadInput;
  }

  const int markers = static_cast<int>(guide.size());
  const int unguided = static_cast<int>(
      std::count_if(guide.begin(), guide.end(), [](const Vec3& g) { return g.hasNaN(); }));
  std::vector<double> rms_m;
  for (const MarkerCandidate& c : candidates) rms_m.push_back(c.fit_rms_m);

  try {
    write_xyz_file(out_path, match.positions_m,
                   fmt::format("extract_markers: marker base centres (m), one line per manifest "
                               "marker of {}\nnan nan nan = not found",
                               guide_path));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "extract_markers: %s\n", e.what());
    return kWriteFailed;
  }

  fmt::print("scan        {}: {} points ({} non-finite skipped)\n", scan_path, report.scan_points,
             report.non_finite_points);
  fmt::print("clusters    {}: {} candidates, {} rejected ({} too few points, {} too many, "
             "{} too wide, {} not a dome)\n",
             report.clusters, report.candidates, report.rejected(), report.too_few_points,
             report.too_many_points, report.too_wide, report.bad_fit);
  if (!rms_m.empty()) {
    fmt::print("sphere fit  RMS median {:.3f} mm, max {:.3f} mm\n", 1e3 * median(rms_m),
               1e3 * *std::max_element(rms_m.begin(), rms_m.end()));
  }
  fmt::print("matched     {} of {} markers, {} missing ({} without a guide); "
             "{} candidates unmatched (gate {:.1f} mm)\n",
             match.matched_count, markers, markers - match.matched_count, unguided,
             match.unmatched_candidates.size(), 1e3 * options.gate_m);
  fmt::print("output      {}\n", out_path);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Marker positions from a raw laser scan of a marked sheet"};
  MarkerExtractionOptions options;
  std::string scan_path, guide_path, out_path;
  std::vector<double> viewpoint;
  app.add_option("--scan", scan_path, "raw scanner points, one \"x y z\" (m) per line")
      ->required();
  app.add_option("--guide", guide_path,
                 "approximate position per manifest marker (m), \"nan nan nan\" for no guess")
      ->required();
  app.add_option("--out", out_path, "marker positions (m) in manifest order, nan when missing")
      ->required();
  app.add_option("--marker-radius-m", options.marker_radius_m, "dome radius (m)")
      ->capture_default_str();
  app.add_option("--viewpoint", viewpoint, "scanner position X Y Z (m), optional")
      ->expected(3);
  app.add_option("--gate-m", options.gate_m, "largest candidate-to-guide distance (m)")
      ->capture_default_str();
  app.add_option("--cluster-tolerance-m", options.cluster_tolerance_m,
                 "largest gap between points of one marker (m)")
      ->capture_default_str();
  app.add_option("--min-points", options.min_points, "fewest points of a marker cluster")
      ->capture_default_str();
  app.add_option("--max-points", options.max_points, "most points of a marker cluster")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);  // prints help, or the error on stderr
    return status == 0 ? 0 : kBadInput;
  }
  if (!viewpoint.empty()) options.viewpoint_m = Vec3(viewpoint[0], viewpoint[1], viewpoint[2]);
  return run(scan_path, guide_path, out_path, options);
}
