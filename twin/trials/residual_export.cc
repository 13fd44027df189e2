#include "twin/trials/residual_export.h"

#include <filesystem>
#include <limits>
#include <ostream>

#include <fmt/format.h>

#include "twin/base/atomic_file.h"
#include "twin/mesh/mesh_io.h"

namespace twin {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void write_stage_csv(const std::filesystem::path& path, const Trial& trial, const TrialStage& stage,
                     const StageFit& fit) {
  const bool markers = stage.observed.has_markers();
  const std::vector<Vec3>& observed = markers ? stage.observed.markers_m : stage.observed.cloud_m;
  write_file_atomically(path, [&](std::ostream& out) {
    out << "index,u_m,v_m,observed_x_m,observed_y_m,observed_z_m,predicted_x_m,predicted_y_m,predicted_z_m,"
           "residual_x_m,residual_y_m,residual_z_m,correspondence_m,nearest_vertex_m\n";
    for (std::size_t i = 0; i < observed.size(); ++i) {
      const Vec3 predicted = markers ? fit.predicted_markers_m[i] : Vec3::Constant(kNaN);
      const Vec3 residual = predicted - observed[i];
      const double correspondence = markers ? fit.correspondence->per_point_m[i] : kNaN;
      out << fmt::format("{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", i,
                         markers ? fmt::format("{:.6f}", trial.marker_uv_m[i].x()) : "",
                         markers ? fmt::format("{:.6f}", trial.marker_uv_m[i].y()) : "", observed[i].x(),
                         observed[i].y(), observed[i].z(), predicted.x(), predicted.y(), predicted.z(),
                         residual.x(), residual.y(), residual.z(), correspondence, fit.nearest.per_point_m[i]);
    }
  });
}

void write_stage_ply(const std::filesystem::path& path, const TrialStage& stage, const StageFit& fit) {
  const bool markers = stage.observed.has_markers();
  const std::vector<Vec3>& observed = markers ? stage.observed.markers_m : stage.observed.cloud_m;
  std::vector<std::pair<Vec3, Vec3>> rows;  // observed, residual
  for (std::size_t i = 0; i < observed.size(); ++i) {
    if (!observed[i].allFinite()) continue;
    // Cloud points have no own material point: their residual is to the nearest vertex.
    Vec3 residual = Vec3::Zero();
    if (markers) {
      residual = fit.predicted_markers_m[i] - observed[i];
    } else {
      const std::vector<int> nearest = nearest_vertices({observed[i]}, fit.x);
      residual = fit.x.segment<3>(3 * nearest[0]) - observed[i];
    }
    rows.emplace_back(observed[i], residual);
  }
  write_file_atomically(path, [&](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment per-marker residuals (predicted - observed), metres\n"
        << "element vertex " << rows.size() << "\n"
        << "property double x\nproperty double y\nproperty double z\n"
        << "property double rx\nproperty double ry\nproperty double rz\nproperty double error_m\nend_header\n";
    for (const auto& [p, r] : rows) {
      out << fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", p.x(), p.y(), p.z(), r.x(), r.y(),
                         r.z(), r.norm());
    }
  });
}

}  // namespace

void write_residual_files(const std::string& directory, const TrialEvaluator& evaluator, const TrialFit& fit) {
  const std::filesystem::path dir(directory);
  create_directories_durably(dir);
  const Trial& trial = evaluator.trial();
  for (std::size_t s = 0; s < fit.stages.size(); ++s) {
    const StageFit& stage_fit = fit.stages[s];
    const TrialStage& stage = trial.stages[s];
    write_stage_csv(dir / (stage.id + "_residuals.csv"), trial, stage, stage_fit);
    write_stage_ply(dir / (stage.id + "_residuals.ply"), stage, stage_fit);
    write_ply(dir / (stage.id + "_predicted.ply"), surface_from_positions(evaluator.model().mesh(), stage_fit.x));
  }
}

}  // namespace twin
