// Blind trial sets (sim_hw/blind_trial_set.h): the generator picks one hidden effect from the
// seed, writes three trials and keeps the truth out of them. The sets here use a 100-triangle
// reference sheet to stay fast; the verdict test (blind_verdict_test.cc) uses the twin's 300.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sim_hw/blind_trial_set.h"
#include "tests/support/child_process.h"
#include "tests/support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
constexpr int kTriangles = 100;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs `scanner_lab blind` on a forced effect; returns its exit code and leaves its output in `log`.
int run_generator(const std::vector<std::string>& args, const fs::path& log) {
  testing_support::ChildProcess child(SCANNER_LAB_EXE, args, {"OMP_NUM_THREADS=1", "OMP_WAIT_POLICY=passive"}, log.string());
  const auto code = child.wait_for_exit(std::chrono::minutes(5));
  REQUIRE(code.has_value());
  return *code;
}

std::vector<std::string> blind_args(std::uint64_t seed, const fs::path& trials, const fs::path& truth,
                                    const std::string& effect) {
  return {"blind", "--seed", std::to_string(seed), "--out", trials.string(), "--truth", truth.string(),
          "--truth-model", "twin", "--triangles", std::to_string(kTriangles), "--effect", effect};
}

// Every file under `directory`, by path relative to it, with its bytes.
std::map<std::string, std::string> files_under(const fs::path& directory) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(directory)) {
    if (entry.is_regular_file()) files[fs::relative(entry.path(), directory).string()] = slurp(entry.path());
  }
  return files;
}

}  // namespace

TEST_CASE("the seed picks every effect about equally often", "[blind]") {
  const auto& names = sim_hw::blind_effect_names();
  REQUIRE(names.size() == 9);
  std::map<std::string, int> counts;
  const int seeds = 9000;
  for (int s = 1; s <= seeds; ++s) ++counts[sim_hw::effect_for_seed(static_cast<std::uint64_t>(s))];
  CHECK(counts.size() == names.size());
  for (const std::string& name : names) {
    // Binomial(9000, 1/9): mean 1000, sigma 31; five sigma either way.
    INFO(name << ": " << counts[name]);
    CHECK(counts[name] > 845);
    CHECK(counts[name] < 1155);
  }
  // The same seed, the same effect; and neighbouring seeds do not all agree.
  CHECK(sim_hw::effect_for_seed(42) == sim_hw::effect_for_seed(42));
  int same = 0;
  for (int s = 1; s < 100; ++s) same += sim_hw::effect_for_seed(s) == sim_hw::effect_for_seed(s + 1);
  CHECK(same < 40);
}

TEST_CASE("hidden effect magnitudes stay in the lab's realistic ranges", "[blind]") {
  const sim_hw::LabSpecimen composite = sim_hw::lab_specimen("composite");
  const double typical_curvature_1_m = 4.0;
  bool softer_warp = false, stiffer_warp = false;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    for (const std::string& effect : sim_hw::blind_effect_names()) {
      const sim_hw::HiddenEffect h =
          sim_hw::draw_hidden_effect(seed, effect, composite, [&] { return typical_curvature_1_m; });
      INFO("seed " << seed << " " << effect << ": " << h.description);
      const twin::Material& m = h.truth;
      const twin::ModelEffects& e = m.effects;
      CHECK(h.effect == effect);
      CHECK(h.creases.size() == (effect == "outside_library" ? 2u : 0u));
      // Only the drawn effect departs from the specimen: everything else is the specimen's.
      CHECK(e.any() == (effect == "rest_curvature" || effect == "nonlinear_bending" || effect == "marker_mass" ||
                        effect == "viscoelastic_relaxation" || effect == "clamp_grip" ||
                        effect == "clamp_slip"));
      const bool orthotropic = effect == "orthotropic_stiffness";
      CHECK((m.bending_rigidity_u_Nm != m.bending_rigidity_v_Nm) == orthotropic);
      CHECK(m.surface_density_kg_m2 == composite.truth.surface_density_kg_m2);
      if (orthotropic) {
        const double ratio = m.bending_rigidity_v_Nm / m.bending_rigidity_u_Nm;
        CHECK(((ratio >= 0.3 && ratio <= 0.6) || (ratio >= 1.7 && ratio <= 2.5)));
        softer_warp |= ratio < 1.0;
        stiffer_warp |= ratio > 1.0;
        // The geometric mean is the specimen's: the effect is the anisotropy, not the level.
        CHECK(std::sqrt(m.bending_rigidity_u_Nm * m.bending_rigidity_v_Nm) ==
              Approx(composite.truth.bending_rigidity_u_Nm).epsilon(1e-12));
      } else if (effect == "rest_curvature") {
        // A roll: the tensor has one non-zero principal curvature, 1/1.5 to 1/0.3 1/m.
        const double trace = e.rest_curvature_uu_1_m + e.rest_curvature_vv_1_m;
        const double det = e.rest_curvature_uu_1_m * e.rest_curvature_vv_1_m - std::pow(e.rest_curvature_uv_1_m, 2);
        CHECK(std::abs(det) < 1e-12);
        CHECK(std::abs(trace) >= 1.0 / 1.5 - 1e-12);
        CHECK(std::abs(trace) <= 1.0 / 0.3 + 1e-12);
      } else if (effect == "nonlinear_bending") {
        const double product = e.bending_stiffening_m2 * typical_curvature_1_m * typical_curvature_1_m;
        CHECK(product >= 0.5);
        CHECK(product <= 3.0);
      } else if (effect == "marker_mass") {
        CHECK(e.marker_mass_kg >= 0.5e-3);
        CHECK(e.marker_mass_kg <= 2e-3);
      } else if (effect == "viscoelastic_relaxation") {
        CHECK(e.relaxation_fraction >= 0.3);
        CHECK(e.relaxation_fraction <= 0.6);
        CHECK(e.relaxation_time_s >= 60.0);
        CHECK(e.relaxation_time_s <= 600.0);
      } else if (effect == "clamp_slip") {
        CHECK(e.clamp_slip_compliance_m_N >= 1e-4 - 1e-15);
        CHECK(e.clamp_slip_compliance_m_N <= 1e-3 + 1e-15);
      } else if (effect == "clamp_grip") {
        CHECK(e.clamp_grip_width_m >= 0.02);
        CHECK(e.clamp_grip_width_m <= 0.06);
        CHECK(e.clamp_grip_strength >= 0.3 - 1e-12);
        CHECK(e.clamp_grip_strength <= 1.5 + 1e-12);
      } else if (effect == "outside_library") {
        for (const sim_hw::Crease& c : h.creases) {
          CHECK(std::abs(c.angle_rad) >= 40.0 * M_PI / 180 - 1e-12);
          CHECK(std::abs(c.angle_rad) <= 80.0 * M_PI / 180 + 1e-12);
        }
        // Folded in four: the creases cross at right angles.
        CHECK(std::abs(h.creases[1].direction_rad - h.creases[0].direction_rad) == Approx(M_PI / 2));
        CHECK(h.creases[0].point_m == h.creases[1].point_m);
      } else {
        CHECK(h.parameters.empty());
      }
    }
  }
  CHECK(softer_warp);
  CHECK(stiffer_warp);
  CHECK_THROWS_WITH(sim_hw::draw_hidden_effect(1, "clamp_creep", composite, [] { return 1.0; }),
                    Catch::Contains("clamp_slip") && Catch::Contains("outside_library"));
}

TEST_CASE("a crease rests the hinges along its line at an angle, and only those", "[blind]") {
  const sim_hw::LabSpecimen composite = sim_hw::lab_specimen("composite");
  twin::ShellModel model(twin::make_rectangular_sheet(1.17, 0.975, 0.1), composite.truth);
  sim_hw::Crease crease;
  crease.point_m = twin::Vec2(0.6, 0.5);
  crease.direction_rad = M_PI / 2;  // along v: the line u = 0.6
  crease.angle_rad = 0.6;
  const int changed = sim_hw::apply_crease(model, crease);
  // A line across the sheet cuts about one hinge per row of triangles (0.975 m / 0.087 m rows).
  CHECK(changed >= 10);
  CHECK(changed <= 40);
  const twin::SheetMesh& mesh = model.mesh();
  int folded = 0;
  for (std::size_t i = 0; i < model.bending().hinges().size(); ++i) {
    const twin::Hinge& hinge = model.bending().hinges()[i];
    const double angle = model.bending().elements()[i].rest_angle_rad;
    const double u = 0.5 * (mesh.rest_uv[hinge.v[0]].x() + mesh.rest_uv[hinge.v[1]].x());
    if (angle != 0.0) {
      ++folded;
      CHECK(std::abs(u - 0.6) < 0.1);  // on the line, within an edge
      CHECK(angle > 0.0);               // all the same way
      CHECK(angle <= 0.6 + 1e-12);
    }
  }
  CHECK(folded > 0);
  CHECK(folded <= changed);
  // The flat sheet is no longer at rest: the crease stores energy there and pushes.
  const twin::VecX flat = [&] {
    twin::VecX x(3 * mesh.vertex_count());
    for (int v = 0; v < mesh.vertex_count(); ++v) x.segment<3>(3 * v) = twin::Vec3(mesh.rest_uv[v].x(), mesh.rest_uv[v].y(), 0.0);
    return x;
  }();
  twin::VecX gradient = twin::VecX::Zero(flat.size());
  CHECK(model.bending().evaluate(flat, &gradient, nullptr, twin::HessianMode::kExact) > 0.0);
  CHECK(gradient.norm() > 0.0);
  // A line that misses the sheet changes nothing.
  twin::ShellModel other(twin::make_rectangular_sheet(1.17, 0.975, 0.1), composite.truth);
  crease.point_m = twin::Vec2(5.0, 5.0);
  CHECK(sim_hw::apply_crease(other, crease) == 0);
}

TEST_CASE("scanner_lab blind writes three trials and keeps the truth out of them", "[blind]") {
  testing_support::TempDir dir("blind_files");
  const fs::path trials = dir / "trials", truth = dir / "truth";
  REQUIRE(run_generator(blind_args(11, trials, truth, "outside_library"), dir / "log.txt") == 0);
  const std::string log = slurp(dir / "log.txt");
  INFO(log);
  for (const std::string& name : sim_hw::blind_trial_names()) {
    const twin::Trial trial = twin::read_trial((trials / name).string());
    CHECK(trial.stages.size() == 5);
    CHECK(trial.marker_uv_m.size() == 289);
    CHECK(fs::exists(truth / name / "5_true.xyz"));
  }
  const nlohmann::json hidden = nlohmann::json::parse(slurp(truth / "hidden_effect.json"));
  CHECK(hidden.at("effect") == "outside_library");
  CHECK(hidden.at("forced") == true);
  CHECK(hidden.at("seed") == 11);
  CHECK(hidden.at("reference_triangles") == kTriangles);
  CHECK(hidden.at("parameters").size() == 6);
  CHECK_NOTHROW(twin::read_material_file((truth / "material.json").string()));
  // Nothing about the effect in the trials, nor on the terminal: not its name, not its kind, not
  // its drawn values (as a writer would print them; fewer digits would match marker coordinates
  // by chance).
  std::vector<std::string> secrets = {"outside_library", "crease", "hidden"};
  for (const auto& [name, value] : hidden.at("parameters").items()) {
    secrets.push_back(name);
    for (int digits : {9, 17}) secrets.push_back(fmt::format("{:.{}g}", value.get<double>(), digits));
  }
  const auto files = files_under(trials);
  CHECK(files.size() == 3 * 6);  // trial.json and five marker files each
  for (const auto& [path, bytes] : files) {
    for (const std::string& secret : secrets) {
      INFO(path << " must not contain '" << secret << "'");
      CHECK(bytes.find(secret) == std::string::npos);
    }
  }
  for (const std::string& secret : secrets) CHECK(log.find(secret) == std::string::npos);
}

TEST_CASE("a blind set is reproducible from its seed, and the effect changes only the sheet", "[blind]") {
  testing_support::TempDir dir("blind_seed");
  REQUIRE(run_generator(blind_args(21, dir / "a", dir / "a_truth", "none"), dir / "a.txt") == 0);
  REQUIRE(run_generator(blind_args(21, dir / "b", dir / "b_truth", "none"), dir / "b.txt") == 0);
  REQUIRE(run_generator(blind_args(21, dir / "c", dir / "c_truth", "orthotropic_stiffness"), dir / "c.txt") == 0);
  const auto a = files_under(dir / "a"), b = files_under(dir / "b"), c = files_under(dir / "c");
  CHECK(a == b);
  CHECK(files_under(dir / "a_truth") == files_under(dir / "b_truth"));
  // Same seed, other effect: the same clamps and protocol (trial.json is about the clamps and
  // the markers' places), but markers that moved by more than the scanner noise.
  REQUIRE(a.size() == c.size());
  for (const std::string& name : sim_hw::blind_trial_names()) {
    const twin::Trial plain = twin::read_trial((dir / "a" / name).string());
    const twin::Trial other = twin::read_trial((dir / "c" / name).string());
    REQUIRE(plain.clamps.size() == other.clamps.size());
    for (std::size_t k = 0; k < plain.clamps.size(); ++k) {
      CHECK(plain.clamps[k].material_point_m == other.clamps[k].material_point_m);
    }
    double moved_m = 0.0;
    int count = 0;
    for (std::size_t s = 0; s < plain.stages.size(); ++s) {
      for (std::size_t m = 0; m < plain.stages[s].observed.markers_m.size(); ++m) {
        const twin::Vec3 d = plain.stages[s].observed.markers_m[m] - other.stages[s].observed.markers_m[m];
        if (d.allFinite()) {
          moved_m += d.norm();
          ++count;
        }
      }
    }
    INFO(name << ": markers moved " << 1e3 * moved_m / count << " mm on average");
    CHECK(moved_m / count > 1e-3);  // noise is 0.3 mm per axis
  }
  // The truth says how far the effect moved the markers, measured against the same trials without
  // it: more than what the noisy files differ by, since the noise is the same in both.
  const nlohmann::json plain_truth = nlohmann::json::parse(slurp(dir / "a_truth" / "hidden_effect.json"));
  const nlohmann::json other_truth = nlohmann::json::parse(slurp(dir / "c_truth" / "hidden_effect.json"));
  CHECK_FALSE(plain_truth.contains("marker_shift_mm"));
  REQUIRE(other_truth.contains("marker_shift_mm"));
  CHECK(other_truth.at("marker_shift_mm").at("mean").get<double>() > 1.0);
  // Another seed: other trials.
  REQUIRE(run_generator(blind_args(22, dir / "d", dir / "d_truth", "none"), dir / "d.txt") == 0);
  CHECK(files_under(dir / "d") != a);
}

TEST_CASE("scanner_lab blind refuses a truth directory inside the trials and an unknown effect", "[blind]") {
  testing_support::TempDir dir("blind_refuse");
  CHECK(run_generator(blind_args(1, dir / "t", dir / "t" / "truth", "none"), dir / "log.txt") == 2);
  CHECK(slurp(dir / "log.txt").find("inside the trials directory") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "t" / "truth" / "hidden_effect.json"));
  // Also when spelt differently, and the same directory for both.
  CHECK_THROWS_WITH(sim_hw::check_blind_directories((dir / "t/").string(), (dir / "u/../t/x/truth").string()),
                    Catch::Contains("inside the trials directory"));
  CHECK_THROWS(sim_hw::check_blind_directories((dir / "t").string(), (dir / "t/").string()));
  CHECK_NOTHROW(sim_hw::check_blind_directories((dir / "t").string(), (dir / "t_truth").string()));
  CHECK_NOTHROW(sim_hw::check_blind_directories((dir / "t" / "a").string(), (dir / "t" / "b").string()));
  CHECK(run_generator(blind_args(1, dir / "u", dir / "u_truth", "gravity_waves"), dir / "log.txt") == 2);
  CHECK(slurp(dir / "log.txt").find("gravity_waves") != std::string::npos);
  // Without --truth the set is not written at all (no default next to the trials).
  CHECK(run_generator({"blind", "--seed", "1", "--out", (dir / "v").string()}, dir / "log.txt") != 0);
  CHECK_FALSE(fs::exists(dir / "v"));
}

TEST_CASE("the typical curvature of markers on a cylinder is one over its radius", "[blind]") {
  sim_hw::LabTrial lab;
  const int rows = 9, cols = 11;
  lab.trial.marker_grid_rows = rows;
  lab.trial.marker_grid_cols = cols;
  const double du = 0.05, dv = 0.04;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) lab.trial.marker_uv_m.push_back(twin::Vec2(c * du, r * dv));
  }
  for (const double radius_m : {0.3, 1.2}) {
    // Rolled along u (markers on the circle by arc length), then along v.
    for (int direction = 0; direction < 2; ++direction) {
      std::vector<twin::Vec3> x;
      for (const twin::Vec2& uv : lab.trial.marker_uv_m) {
        const double arc = direction == 0 ? uv.x() : uv.y(), across = direction == 0 ? uv.y() : uv.x();
        const double phi = arc / radius_m;
        x.push_back(twin::Vec3(radius_m * std::sin(phi), across, radius_m * (1.0 - std::cos(phi))));
      }
      lab.true_markers_m = {x, x};
      INFO("radius " << radius_m << " along " << (direction == 0 ? "u" : "v"));
      // The chord's second difference is 4 R sin^2(s / 2R) / s^2 = (1/R) (1 - s^2 / 12 R^2 ...).
      CHECK(sim_hw::typical_marker_curvature_1_m(lab) == Approx(1.0 / radius_m).epsilon(0.01));
    }
  }
  // A flat sheet has none.
  std::vector<twin::Vec3> flat;
  for (const twin::Vec2& uv : lab.trial.marker_uv_m) flat.push_back(twin::Vec3(uv.x(), uv.y(), 1.0));
  lab.true_markers_m = {flat};
  CHECK(sim_hw::typical_marker_curvature_1_m(lab) == Approx(0.0).margin(1e-9));
}

TEST_CASE("for one seed every effect gives the same trial.json: only the sheet's shape differs", "[blind]") {
  // trial.json holds the specimen, markers, clamps, their measured poses and the stage times: if
  // any of it depended on the effect (a mass including the markers, a protocol drawn after the
  // effect), it would give the effect away without looking at the sheet.
  testing_support::TempDir dir("blind_same_json");
  std::map<std::string, std::string> first;
  std::map<std::string, std::uint64_t> first_lab_seed;
  int compared = 0, retried = 0;
  for (const std::string& effect : sim_hw::blind_effect_names()) {
    sim_hw::BlindSetConfig config;
    config.seed = 41;
    config.truth_model = sim_hw::TruthModel::kTwin;
    config.triangles = kTriangles;
    config.forced_effect = effect;
    config.measure_effect = false;
    const sim_hw::BlindTrialSet set = sim_hw::make_blind_trial_set(config);
    sim_hw::write_blind_trial_set(set, (dir / effect).string(), (dir / (effect + "_truth")).string());
    for (std::size_t k = 0; k < sim_hw::blind_trial_names().size(); ++k) {
      const std::string& name = sim_hw::blind_trial_names()[k];
      const std::string json = slurp(dir / effect / name / "trial.json");
      REQUIRE_FALSE(json.empty());
      if (!first.count(name)) {
        first[name] = json;
        first_lab_seed[name] = set.labs[k].seed;
      }
      // A reference sheet that failed (a strong effect can make a protocol unsimulable) is
      // repeated with the next protocol, as a real lab repeats a botched trial: that trial
      // differs, and says only that a trial was repeated.
      if (set.labs[k].seed != first_lab_seed[name]) {
        ++retried;
        continue;
      }
      ++compared;
      INFO(effect << " " << name);
      CHECK(json == first[name]);
    }
  }
  INFO(retried << " trials repeated");
  CHECK(compared >= 4 * retried);
}
