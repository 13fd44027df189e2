#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>

#include "tests/diagnosis/svg_check.h"
#include "tests/diagnosis/synthetic_field.h"
#include "tests/support/temp_dir.h"
#include "twin/diagnosis/diagnosis_report.h"
#include "twin/diagnosis/svg_figures.h"

using namespace diagnosis_test;
namespace dx = twin::diagnosis;

namespace {

dx::ReportPhase phase(const std::string& name, unsigned seed, int stages, bool with_after) {
  SyntheticOptions o;
  o.seed = seed;
  o.stages = stages;
  const auto model_error = [](const Vec2& uv, int) { return Vec3(0, 0, 2e-3 * uv.x()); };
  dx::ReportPhase p;
  p.name = name;
  p.before = synthetic_field(o, model_error);
  // A marker under a clamp is not seen: drop one from the first stage.
  p.before.samples.erase(p.before.samples.begin());
  p.before.stages[0].samples -= 1;
  p.before_analysis = dx::analyse_residuals(p.before, o.sigma_m);
  if (with_after) {
    o.seed += 100;
    p.after = synthetic_field(o, no_error);
    p.after_analysis = dx::analyse_residuals(*p.after, o.sigma_m);
  }
  return p;
}

dx::ReportData report_data(bool with_after) {
  dx::ReportData d;
  d.verdict_line = with_after ? "effect: orthotropic_stiffness" : "none: no missing effect supported";
  d.after_label = "with orthotropic_stiffness";
  d.noise_floor_m = 0.3e-3;
  d.parameters = {{"parameter", "value", "95 % interval"}, {{"bending_v", "0.012", "[0.010, 0.014]"}}};
  d.candidates = {{"effect", "score", "p"}, {{"orthotropic_stiffness", "812.4", "1e-30"}, {"rest_curvature", "12.1", "0.01"}}};
  d.notes = {"train: 1 trial, held-out: 1 trial"};
  d.phases = {phase("train", 1, 3, with_after), phase("held-out", 2, 2, with_after)};
  return d;
}

}  // namespace

TEST_CASE("the report is markdown with well-formed SVG maps, one circle per seen marker per panel", "[diagnosis]") {
  testing_support::TempDir dir("diagnosis_report");
  const dx::ReportData data = report_data(true);
  dx::write_report(data, dir / "out");
  const std::filesystem::path out = dir / "out";
  REQUIRE(std::filesystem::exists(out / "report.md"));
  CHECK_FALSE(std::filesystem::exists(out / ".report.tmp"));
  const std::string md = read_text((out / "report.md").string());
  CHECK(md.find("**Verdict:** effect: orthotropic_stiffness") != std::string::npos);
  CHECK(md.find("| orthotropic_stiffness | 812.4 | 1e-30 |") != std::string::npos);
  CHECK(md.find("figures/stage_errors.svg") != std::string::npos);
  for (const dx::ReportPhase& p : data.phases)
    for (std::size_t s = 0; s < p.before.stages.size(); ++s) {
      const std::string name = (p.name == "train" ? "train" : "held_out") + std::string("_stage_") + std::to_string(s + 1) + ".svg";
      INFO(name);
      CHECK(md.find("figures/" + name) != std::string::npos);
      const std::string svg = read_text((out / "figures" / name).string());
      CHECK(svg_problem(svg).empty());
      INFO(svg_problem(svg));
      CHECK(count_of(svg, "<circle") == p.before.stages[s].samples + p.after->stages[s].samples);
    }
  const std::string bars = read_text((out / "figures" / "stage_errors.svg").string());
  CHECK(svg_problem(bars).empty());
  CHECK(count_of(bars, "<rect") >= 2 * (3 + 2));  // a bar before and after for every stage
  // The 'before' maps of the model error show significant regions outlined.
  CHECK(count_of(read_text((out / "figures" / "train_stage_2.svg").string()), "stroke-dasharray") > 0);
}

TEST_CASE("a second report replaces the first, and without an effect there are no after panels", "[diagnosis]") {
  testing_support::TempDir dir("diagnosis_report");
  dx::write_report(report_data(true), dir / "out");
  const dx::ReportData none = report_data(false);
  dx::write_report(none, dir / "out");
  const std::string md = read_text((dir / "out" / "report.md").string());
  CHECK(md.find("none: no missing effect supported") != std::string::npos);
  const std::string svg = read_text((dir / "out" / "figures" / "train_stage_1.svg").string());
  CHECK(svg_problem(svg).empty());
  CHECK(count_of(svg, "<circle") == none.phases[0].before.stages[0].samples);
}

TEST_CASE("the terminal summary fits one screen and carries the verdict", "[diagnosis]") {
  for (bool with_after : {true, false}) {
    dx::ReportData data = report_data(with_after);
    for (int k = 0; k < 30; ++k) data.candidates.rows.push_back({"candidate " + std::to_string(k), "1.0", "0.5"});
    const std::string text = dx::terminal_summary(data);
    std::istringstream lines(text);
    std::string line;
    int count = 0;
    while (std::getline(lines, line)) {
      ++count;
      CHECK(line.size() <= 100);
    }
    CHECK(count <= 25);
    CHECK(text.find(data.verdict_line) != std::string::npos);
    CHECK(text.find("sigma 0.300 mm") != std::string::npos);
    CHECK(text.find("\n  bending_v  0.012  [0.010, 0.014]\n") != std::string::npos);
  }
}

TEST_CASE("SVG text is escaped and colours run blue through white to red", "[diagnosis]") {
  CHECK(dx::xml_escape("a<b & \"c\">") == "a&lt;b &amp; &quot;c&quot;&gt;");
  CHECK(dx::diverging_colour(0.0, 1.0) == "#ffffff");
  CHECK(dx::diverging_colour(5.0, 1.0) == "#b2182b");
  CHECK(dx::diverging_colour(-1.0, 1.0) == "#2166ac");
  CHECK(svg_problem("<svg><g></svg>") != "");
  CHECK(svg_problem("<svg><circle r=\"1\"/></svg>") == "");
}
