#include "twin/diagnosis/diagnosis_report.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "twin/base/atomic_file.h"
#include "twin/diagnosis/svg_figures.h"

namespace twin::diagnosis {
namespace {

namespace fs = std::filesystem;

// Mean length of a 3D Gaussian noise vector of sigma per coordinate: sigma sqrt(8 / pi). The
// mean correspondence error of a perfect twin.
double noise_floor_mean_error_m(double sigma_m) { return sigma_m * std::sqrt(8.0 / std::numbers::pi); }

// The shared colour limit (mm): the 98th percentile of |normal residual| over every map, at
// least 3 sigma, so maps before and after are comparable and noise alone looks pale.
double colour_limit_mm(const ReportData& data) {
  std::vector<double> v;
  for (const ReportPhase& p : data.phases) {
    for (const ResidualSample& s : p.before.samples) v.push_back(std::abs(1e3 * s.normal_residual_m));
    if (p.after)
      for (const ResidualSample& s : p.after->samples) v.push_back(std::abs(1e3 * s.normal_residual_m));
  }
  double limit = 3e3 * data.noise_floor_m;
  if (!v.empty()) {
    const auto k = static_cast<std::ptrdiff_t>(0.98 * (v.size() - 1));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    limit = std::max(limit, v[k]);
  }
  return limit > 0.0 ? limit : 1.0;
}

std::string markdown_table(const ReportTable& t) {
  std::ostringstream s;
  s << "| " << fmt::format("{}", fmt::join(t.header, " | ")) << " |\n|";
  for (std::size_t i = 0; i < t.header.size(); ++i) s << "---|";
  s << "\n";
  for (const auto& row : t.rows) s << "| " << fmt::format("{}", fmt::join(row, " | ")) << " |\n";
  return s.str();
}

std::string file_stem(const std::string& phase, int stage) {
  std::string p;
  for (char c : phase) p += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return fmt::format("{}_stage_{}", p, stage + 1);
}

std::string yes(bool b) { return b ? "**yes**" : "no"; }

void write_phase_section(std::ostream& md, const ReportData& data, const ReportPhase& p) {
  md << "\n## " << p.name << " trials\n\n";
  md << "Before (trials: " << p.before.trials.size() << ", marker stages: " << p.before.stages.size() << "):\n\n";
  for (const std::string& line : p.before_analysis.sentences) md << "- " << line << "\n";
  if (p.after_analysis) {
    md << "\n" << data.after_label << ":\n\n";
    for (const std::string& line : p.after_analysis->sentences) md << "- " << line << "\n";
  }
  md << "\n| stage | markers | mean error before (mm) | RMS/coord before (mm) | p before | significant before |"
     << (p.after ? " mean error after (mm) | RMS/coord after (mm) | p after | significant after |" : "") << "\n|";
  for (int i = 0; i < (p.after ? 10 : 6); ++i) md << "---|";
  md << "\n";
  for (std::size_t s = 0; s < p.before.stages.size(); ++s) {
    const ChiSquareTest& b = p.before_analysis.stages.at(s).test;
    md << fmt::format("| {} | {} | {:.3f} | {:.3f} | {:.2g} | {} |", p.before.stages[s].label, p.before.stages[s].samples,
                      1e3 * p.before.stages[s].mean_error_m, 1e3 * b.rms_m, b.p_value, yes(b.significant));
    if (p.after && s < p.after->stages.size()) {
      const ChiSquareTest& a = p.after_analysis->stages.at(s).test;
      md << fmt::format(" {:.3f} | {:.3f} | {:.2g} | {} |", 1e3 * p.after->stages[s].mean_error_m, 1e3 * a.rms_m, a.p_value,
                        yes(a.significant));
    }
    md << "\n";
  }
  md << "\nResidual maps (normal component of observed - predicted, mm; dashed boxes: significant regions):\n\n";
  for (std::size_t s = 0; s < p.before.stages.size(); ++s)
    md << "![" << p.before.stages[s].label << "](figures/" << file_stem(p.name, static_cast<int>(s)) << ".svg)\n";
}

void write_figures(const ReportData& data, const fs::path& dir) {
  const double limit = colour_limit_mm(data);
  std::vector<std::string> series;
  std::vector<BarGroup> groups;
  for (const ReportPhase& p : data.phases) {
    series.push_back(p.name + " before");
    if (p.after) series.push_back(p.name + " " + data.after_label);
  }
  std::size_t column = 0;
  for (const ReportPhase& p : data.phases) {
    for (std::size_t s = 0; s < p.before.stages.size(); ++s) {
      std::vector<MapPanel> panels = {{"before: " + p.before.stages[s].label, &p.before, &p.before_analysis.stages.at(s),
                                       static_cast<int>(s)}};
      BarGroup g{p.name + " " + p.before.stages[s].label, std::vector<double>(series.size(), NAN)};
      g.values[column] = 1e3 * p.before.stages[s].mean_error_m;
      if (p.after && s < p.after->stages.size()) {
        panels.push_back({data.after_label + ": " + p.after->stages[s].label, &*p.after, &p.after_analysis->stages.at(s),
                          static_cast<int>(s)});
        g.values[column + 1] = 1e3 * p.after->stages[s].mean_error_m;
      }
      groups.push_back(g);
      const std::string svg = residual_map_svg(panels, limit);
      write_file_atomically(dir / (file_stem(p.name, static_cast<int>(s)) + ".svg"), [&](std::ostream& o) { o << svg; });
    }
    column += p.after ? 2 : 1;
  }
  const std::string chart = bar_chart_svg("Mean correspondence error per stage", series, groups,
                                          1e3 * noise_floor_mean_error_m(data.noise_floor_m), "noise floor");
  write_file_atomically(dir / "stage_errors.svg", [&](std::ostream& o) { o << chart; });
}

void write_markdown(const ReportData& data, const fs::path& path) {
  write_file_atomically(path, [&](std::ostream& md) {
    md << "# " << data.title << "\n\n**Verdict:** " << data.verdict_line << "\n\n";
    md << fmt::format("Noise floor: sigma = {:.3f} mm per coordinate ({}); a perfect twin's mean marker error is "
                      "{:.3f} mm.\n",
                      1e3 * data.noise_floor_m, data.noise_source.empty() ? std::string("given") : "estimated on " + data.noise_source,
                      1e3 * noise_floor_mean_error_m(data.noise_floor_m));
    if (!data.parameters.empty()) md << "\n## Fitted parameters\n\n" << markdown_table(data.parameters);
    if (!data.candidates.empty()) md << "\n## Candidate effects\n\n" << markdown_table(data.candidates);
    if (!data.notes.empty()) {
      md << "\n## Evidence\n\n";
      for (const std::string& n : data.notes) md << "- " << n << "\n";
    }
    md << "\n## Error per stage\n\n![mean error per stage](figures/stage_errors.svg)\n";
    for (const ReportPhase& p : data.phases) write_phase_section(md, data, p);
  });
}

}  // namespace

void write_report(const ReportData& data, const fs::path& out_dir) {
  std::error_code ec;
  try {
    create_directories_durably(out_dir);
    const fs::path tmp = out_dir / ".report.tmp";
    fs::remove_all(tmp, ec);
    create_directories_durably(tmp / "figures");
    // Each file is flushed with its directory as it is written (atomic_file.h).
    write_figures(data, tmp / "figures");
    write_markdown(data, tmp / "report.md");
    // Complete: move into place, figures first so report.md never points at missing pictures,
    // each move flushed before the next so that a crash cannot keep the second without the first.
    fs::remove_all(out_dir / "figures", ec);
    fs::rename(tmp / "figures", out_dir / "figures", ec);
    if (ec) throw std::runtime_error("cannot move figures into " + out_dir.string() + ": " + ec.message());
    sync_directory(out_dir);
    fs::rename(tmp / "report.md", out_dir / "report.md", ec);
    if (ec) throw std::runtime_error("cannot write " + (out_dir / "report.md").string() + ": " + ec.message());
    sync_directory(out_dir);
    fs::remove_all(tmp, ec);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("report: ") + e.what());
  }
}

}  // namespace twin::diagnosis
