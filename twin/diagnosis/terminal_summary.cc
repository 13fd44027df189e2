// terminal_summary() of diagnosis_report.h: the verdict and its evidence on one screen.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "twin/diagnosis/diagnosis_report.h"

namespace twin::diagnosis {
namespace {

constexpr std::size_t kMaxLines = 25;
constexpr std::size_t kMaxColumns = 100;

double mean_error_mm(const ResidualField& f) {
  double sum = 0.0;
  for (const ResidualSample& s : f.samples) sum += s.error_m();
  return f.samples.empty() ? NAN : 1e3 * sum / static_cast<double>(f.samples.size());
}

// Word-wraps text to kMaxColumns, continuation lines indented by `indent`.
std::vector<std::string> wrap(const std::string& text, const std::string& indent) {
  if (text.size() <= kMaxColumns) return {text};  // as it is, spacing included
  std::vector<std::string> lines;
  // Leading spaces are kept (table rows are indented under their heading).
  const std::size_t lead = std::min(text.find_first_not_of(' '), text.size());
  std::string line = text.substr(0, lead), word;
  auto flush_word = [&] {
    if (word.empty()) return;
    const bool fresh = line.size() == lead || line == indent;
    if (!fresh && line.size() + 1 + word.size() > kMaxColumns) {
      lines.push_back(line);
      line = indent;
    }
    if (!fresh && line != indent) line += ' ';
    line += word;
    word.clear();
  };
  for (char c : text.substr(lead)) {
    if (c == ' ') flush_word();
    else word += c;
  }
  flush_word();
  if (line.size() > lead) lines.push_back(line);
  for (std::string& l : lines)
    if (l.size() > kMaxColumns) l = l.substr(0, kMaxColumns - 3) + "...";
  return lines;
}

}  // namespace

std::string terminal_summary(const ReportData& data) {
  std::vector<std::string> lines;
  auto add = [&](const std::string& text, const std::string& indent = "    ") {
    for (const std::string& l : wrap(text, indent)) lines.push_back(l);
  };
  add(data.title);
  add("Verdict: " + data.verdict_line);
  add(fmt::format("Noise floor: sigma {:.3f} mm per coordinate ({}), perfect-twin mean error {:.3f} mm",
                  1e3 * data.noise_floor_m, data.noise_source.empty() ? "given" : "estimated",
                  1e3 * data.noise_floor_m * std::sqrt(8.0 / std::numbers::pi)));
  for (const ReportPhase& p : data.phases) {
    std::string line = fmt::format("{}: mean error {:.3f} mm, {}/{} stages and {} regions significant", p.name,
                                   mean_error_mm(p.before), p.before_analysis.significant_stage_count(),
                                   p.before.stages.size(), p.before_analysis.significant_region_count());
    if (p.after && p.after_analysis)
      line += fmt::format(" -> {}: {:.3f} mm, {}/{} stages, {} regions", data.after_label, mean_error_mm(*p.after),
                          p.after_analysis->significant_stage_count(), p.after->stages.size(),
                          p.after_analysis->significant_region_count());
    add(line);
  }
  if (!data.parameters.empty()) {
    add("Parameters:");
    for (const auto& row : data.parameters.rows) add("  " + fmt::format("{}", fmt::join(row, "  ")));
  }
  // The structure findings of the first phase (train) before any effect: why a name was sought.
  if (!data.phases.empty()) {
    const auto& sentences = data.phases.front().before_analysis.sentences;
    for (std::size_t i = 1; i < sentences.size() && lines.size() + 2 < kMaxLines - 6; ++i) add("* " + sentences[i], "  ");
  }
  if (!data.candidates.empty()) {
    add("Candidates: " + fmt::format("{}", fmt::join(data.candidates.header, " | ")));
    for (const auto& row : data.candidates.rows) {
      if (lines.size() + 1 >= kMaxLines) break;
      add("  " + fmt::format("{}", fmt::join(row, " | ")));
    }
  }
  if (lines.size() > kMaxLines) {
    lines.resize(kMaxLines);
    lines.back() = "... (see report.md)";
  }
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

}  // namespace twin::diagnosis
