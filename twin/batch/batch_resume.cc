#include "twin/batch/batch_resume.h"

#include <stdexcept>

#include <fmt/format.h>

#include "twin/base/json_field.h"

namespace twin::batch {

namespace fs = std::filesystem;

std::optional<BatchRow> finished_row(const fs::path& dir, const BatchMaterial& material) {
  const fs::path file = dir / "done.json";
  std::error_code ec;
  const bool exists = fs::exists(file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot tell whether the material is finished: " + ec.message());
  if (!exists) return std::nullopt;
  BatchRow row;
  try {
    const nlohmann::json j = JsonField::parse_file(file.string());
    const JsonField root(j, file.string());
    if (!root.is_object()) root.fail("must be a JSON object");
    if (root["fingerprint"].string() != material.fingerprint) return std::nullopt;  // another entry: redo
    row = row_from_field(root["row"]);
    if (row.name != material.name) root["row"]["name"].fail("is \"" + row.name + "\", not \"" + material.name + "\"");
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format(
        "{} (a corrupt batch resume file: expected the record `twin batch` writes when a material is finished, "
        "{{\"fingerprint\": \"<manifest entry>\", \"row\": {{\"name\", \"status\", \"verdict\", \"effect\", "
        "\"held_out_before_mm\", \"held_out_after_mm\", \"noise_sigma_mm\", \"seconds\", \"error\"}}}}). "
        "Move it away or delete it to diagnose {} again",
        e.what(), material.name));
  }
  if (!fs::is_regular_file(dir / "material.json")) {
    throw std::runtime_error(fmt::format("{}: records {} as finished, but {} is missing. Delete the done.json to "
                                         "diagnose it again",
                                         file.string(), material.name, (dir / "material.json").string()));
  }
  row.status = "already done";
  return row;
}

std::string interrupted_run(const fs::path& dir) {
  const fs::path file = dir / "running.json";
  std::error_code ec;
  if (!fs::exists(file, ec)) return "";
  try {
    const nlohmann::json j = JsonField::parse_file(file.string());
    const JsonField root(j, file.string());
    const auto integer = [](const JsonField& f) {
      if (!f.json().is_number_integer()) f.fail("must be an integer");
      return f.json().get<long long>();
    };
    return fmt::format("an earlier run stopped while diagnosing it (rank {}, pid {} on {}, started {}); diagnosed again",
                       integer(root["rank"]), integer(root["pid"]), root["host"].string(), root["started"].string());
  } catch (const std::exception& e) {
    return fmt::format("an earlier run stopped while diagnosing it (its running.json is unreadable: {}); diagnosed again",
                       e.what());
  }
}

}  // namespace twin::batch
