#pragma once
// What an earlier `twin batch` run left in a material's directory OUT/NAME (batch_runner.h): its
// done.json, read back so that the material is not diagnosed again, and the running.json of a
// run that stopped while diagnosing it.

#include <filesystem>
#include <optional>
#include <string>

#include "twin/batch/batch_manifest.h"
#include "twin/batch/batch_runner.h"

namespace twin::batch {

// The row of OUT/NAME/done.json ("already done") when it was made from this very manifest entry;
// nullopt when there is no done.json or it was made from another entry (the material is then
// diagnosed again). A done.json that is not what `twin batch` writes (not JSON, a field missing or
// of another type), or one whose material.json is gone, throws std::runtime_error naming the file
// and what was expected: a finished result is at stake, so it is never silently diagnosed again.
std::optional<BatchRow> finished_row(const std::filesystem::path& dir, const BatchMaterial& material);

// What a running.json left by an earlier run says (rank, process, host, start), or "" when there
// is none. One that cannot be read is named, with why, in the note; the material is diagnosed
// again either way, as it never finished.
std::string interrupted_run(const std::filesystem::path& dir);

}  // namespace twin::batch
