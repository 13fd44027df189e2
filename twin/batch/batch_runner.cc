#include "twin/batch/batch_runner.h"

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <optional>

#include <fmt/chrono.h>
#include <fmt/format.h>

#include "twin/base/atomic_file.h"
#include "twin/base/json_field.h"
#include "twin/batch/batch_resume.h"
#include "twin/distributed/byte_codec.h"
#include "twin/model/material.h"

namespace twin::batch {
namespace {

namespace fs = std::filesystem;

// OUT/NAME/running.json: who is diagnosing the material, while it runs.
void write_running_marker(const fs::path& dir, int rank) {
  char host[256] = "";
  if (gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  const nlohmann::json marker = {{"rank", rank},
                                 {"pid", static_cast<long>(getpid())},
                                 {"host", host},
                                 {"started", fmt::format("{:%Y-%m-%dT%H:%M:%SZ}", fmt::gmtime(std::time(nullptr)))}};
  write_file_atomically(dir / "running.json", [&](std::ostream& o) { o << marker.dump(2) << "\n"; });
}

// `team`: the ranks the diagnosis runs on together (null: this process alone); its rank 0
// writes material.json, as run_diagnosis writes its report there alone.
BatchRow diagnose_material(const BatchManifest& manifest, const BatchMaterial& material, const fs::path& dir,
                           const BatchOptions& options, distributed::RankGroup* team) {
  const auto start = std::chrono::steady_clock::now();
  BatchRow row;
  row.name = material.name;
  diagnosis::DiagnoseOptions o = manifest.diagnose;
  o.train = material.train;
  o.test = material.test;
  o.material = material.material;
  o.report = dir.string();
  o.ranks = team;
  const bool leads = !team || team->rank() == 0;
  if (options.progress && leads) {
    o.progress = [&](const std::string& line) { options.progress(material.name + ": " + line); };
  }
  try {
    const diagnosis::DiagnoseOutcome outcome = diagnosis::run_diagnosis(o);
    if (leads) write_material_file((dir / "material.json").string(), outcome.material);
    row.status = "done";
    row.verdict = outcome.verdict.verdict;
    row.effect = outcome.verdict.effect.value_or("");
    row.held_out_before_mm = 1e3 * outcome.base_test.mean_correspondence_m;
    row.held_out_after_mm = outcome.after_test ? 1e3 * outcome.after_test->mean_correspondence_m : 0.0;
    row.noise_sigma_mm = 1e3 * outcome.sigma_m;
  } catch (const std::exception& e) {
    row.status = "failed";
    row.error = e.what();
  }
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

}  // namespace

nlohmann::json row_json(const BatchRow& r) {
  return {{"name", r.name},
          {"status", r.status},
          {"verdict", r.verdict},
          {"effect", r.effect},
          {"held_out_before_mm", r.held_out_before_mm},
          {"held_out_after_mm", r.held_out_after_mm},
          {"noise_sigma_mm", r.noise_sigma_mm},
          {"seconds", r.seconds},
          {"error", r.error},
          {"note", r.note}};
}

BatchRow row_from_field(const JsonField& f) {
  BatchRow r;
  r.name = f["name"].string();
  r.status = f["status"].string();
  r.verdict = f["verdict"].string();
  r.effect = f["effect"].string();
  r.held_out_before_mm = f["held_out_before_mm"].number("mm");
  r.held_out_after_mm = f["held_out_after_mm"].number("mm");
  r.noise_sigma_mm = f["noise_sigma_mm"].number("mm");
  r.seconds = f["seconds"].number("s");
  r.error = f["error"].string();
  if (auto note = f.optional("note")) r.note = note->string();  // absent in the done.json of runs before it existed
  return r;
}

BatchRow row_from_json(const nlohmann::json& j) { return row_from_field(JsonField(j, "a batch row")); }

namespace {

// What a team's leader tells its other ranks: diagnose material `index` with me, or (-1) the
// batch is over.
void tell_team(distributed::RankGroup& team, int index) {
  distributed::ByteWriter w;
  w.put<std::int32_t>(index);
  team.broadcast_from_rank0(w.bytes());
}

// A team's other ranks: every material their leader diagnoses, with it, until it says stop.
void follow_team_leader(const BatchManifest& manifest, const BatchOptions& options, distributed::RankGroup& team) {
  for (;;) {
    const std::string bytes = team.broadcast_from_rank0("");
    distributed::ByteReader r(bytes);
    const int index = r.get<std::int32_t>();
    if (index < 0) return;
    const BatchMaterial& material = manifest.materials.at(static_cast<std::size_t>(index));
    diagnose_material(manifest, material, fs::path(options.out) / material.name, options, &team);
  }
}

// One material: read back when finished before, else diagnosed into OUT/NAME (with `team`,
// whose leader this rank is, when there is one).
BatchRow run_material(const BatchManifest& manifest, std::size_t i, const BatchOptions& options, int rank,
                      distributed::RankGroup* team) {
  const BatchMaterial& material = manifest.materials[i];
  const fs::path dir = fs::path(options.out) / material.name;
  const std::size_t count = manifest.materials.size();
  if (std::optional<BatchRow> row = finished_row(dir, material)) {
    if (options.progress) options.progress(fmt::format("{} ({}/{}): already done", material.name, i + 1, count));
    return *row;
  }
  create_directories_durably(dir);
  const std::string interrupted = interrupted_run(dir);
  // An earlier run's files must not pass for this one's (a material.json beside a failure).
  for (const char* stale : {"done.json", "failed.json", "material.json"}) fs::remove(dir / stale);
  write_running_marker(dir, rank);
  if (options.progress) {
    options.progress(fmt::format("{} ({}/{}): diagnosing{}", material.name, i + 1, count,
                                 interrupted.empty() ? "" : " (" + interrupted.substr(0, interrupted.find(';')) + ")"));
  }
  if (team) tell_team(*team, static_cast<int>(i));
  BatchRow row = diagnose_material(manifest, material, dir, options, team);
  row.note = interrupted;
  const nlohmann::json record = {{"fingerprint", material.fingerprint}, {"row", row_json(row)}};
  write_file_atomically(dir / (row.status == "done" ? "done.json" : "failed.json"),
                        [&](std::ostream& o) { o << record.dump(2) << "\n"; });
  fs::remove(dir / "running.json");
  if (options.progress) {
    options.progress(row.status == "done"
                         ? fmt::format("{}: {}{} in {:.0f} s", material.name, row.verdict,
                                       row.effect.empty() ? "" : " (" + row.effect + ")", row.seconds)
                         : fmt::format("{}: FAILED: {}", material.name, row.error));
  }
  return row;
}

}  // namespace

BatchResult run_batch(const BatchManifest& manifest, const BatchOptions& options) {
  distributed::SingleProcess single;
  distributed::RankGroup& ranks = options.ranks ? *options.ranks : single;
  const fs::path out(options.out);
  // On every rank: an unwritable OUT then stops them all here alike, before the farm, rather than
  // rank 0 alone while the others wait for work.
  create_directories_durably(out);
  const int rank = ranks.rank();
  // Teams of ranks_per_material ranks: materials go to the teams' leaders, each material's
  // refit searches over its team.
  std::optional<distributed::Teams> teams;
  if (options.ranks_per_material > 1) teams = ranks.split_into_teams(options.ranks_per_material);
  distributed::RankGroup* team = teams ? teams->team.get() : nullptr;
  std::vector<std::string> results;
  if (teams && !teams->leaders) {
    follow_team_leader(manifest, options, *team);
  } else {
    // A material's own failure is its row; an exception here (OUT unwritable) becomes a failed
    // row too, so that a rank never throws out of the farm and leaves rank 0 waiting.
    distributed::RankGroup& farm = teams ? *teams->leaders : ranks;
    results = farm.farm_to_rank0(static_cast<int>(manifest.materials.size()), [&](int i) {
      try {
        return row_json(run_material(manifest, static_cast<std::size_t>(i), options, rank, team)).dump();
      } catch (const std::exception& e) {
        BatchRow row;
        row.name = manifest.materials[static_cast<std::size_t>(i)].name;
        row.status = "failed";
        row.error = fmt::format("rank {}: {}", rank, e.what());
        return row_json(row).dump();
      }
    });
    if (team) tell_team(*team, -1);
  }
  teams.reset();  // before the world's group, as split_into_teams asks
  BatchResult result;
  if (rank != 0) return result;
  for (const std::string& text : results) {
    BatchRow row = row_from_json(nlohmann::json::parse(text));
    ++(row.status == "done" ? result.done : row.status == "failed" ? result.failed : result.already_done);
    result.rows.push_back(std::move(row));
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const BatchRow& r : result.rows) rows.push_back(row_json(r));
  write_file_atomically(out / "summary.json", [&](std::ostream& o) {
    o << nlohmann::json{{"manifest", manifest.source}, {"ranks", ranks.size()}, {"materials", rows}}.dump(2) << "\n";
  });
  write_file_atomically(out / "summary.md", [&](std::ostream& o) { o << summary_table(result); });
  return result;
}

std::string summary_table(const BatchResult& result) {
  std::string s = "| material | status | verdict | effect | held-out before (mm) | after (mm) | noise sigma (mm) | "
                  "seconds | error | note |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const BatchRow& r : result.rows) {
    const bool ok = r.status != "failed";
    s += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.0f} | {} | {} |\n", r.name, r.status, ok ? r.verdict : "-",
                     r.effect.empty() ? "-" : r.effect, ok ? fmt::format("{:.3f}", r.held_out_before_mm) : "-",
                     ok && r.held_out_after_mm > 0.0 ? fmt::format("{:.3f}", r.held_out_after_mm) : "-",
                     ok ? fmt::format("{:.3f}", r.noise_sigma_mm) : "-", r.seconds, r.error, r.note);
  }
  s += fmt::format("\n{} diagnosed now, {} already done, {} failed\n", result.done, result.already_done, result.failed);
  return s;
}

}  // namespace twin::batch
