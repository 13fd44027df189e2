#pragma once
// `twin batch`: diagnoses every material of a manifest (batch_manifest.h) one after another and
// writes, under the output directory OUT:
//   OUT/NAME/            the diagnosis report (verdict.json, report.md, material_augmented.json
//                        when an effect is named; twin/diagnosis/diagnose.h)
//   OUT/NAME/material.json   the material as characterised (with the named effect, else the
//                        base fit), a material file the twin reads
//   OUT/NAME/done.json   written last, atomically: the material is finished. It records the
//                        manifest entry it was made from and the summary row.
//   OUT/NAME/failed.json when the diagnosis threw: the error. The other materials go on.
//   OUT/NAME/running.json while it is being diagnosed: which rank, process and host, since when.
//                        Removed once done.json or failed.json is written; one found by a later
//                        run means that run's predecessor stopped there (killed, say), and the
//                        material's row says so when it is diagnosed again.
//   OUT/summary.json, OUT/summary.md   one row per material, in manifest order.
// Resuming: a material whose done.json records the same manifest entry (trials, start material,
// diagnose options) is not redone; its row is read back (batch_resume.h). A corrupt done.json is
// the material's failure, naming the file; it is left as it is, never silently redone. Anything else (never run, interrupted,
// failed, or changed in the manifest) is diagnosed afresh, its old done.json, failed.json and
// material.json removed first, so that an interrupted run never leaves a material looking finished.
// Over MPI ranks (options.ranks, twin/distributed/rank_group.h) whole materials are handed out
// to whichever rank is free; each rank writes its materials' files (OUT must be one directory
// all ranks see) and rank 0 the summary. The files are those of a serial run: each material is
// diagnosed by the same code on the same inputs, wherever it runs. With teams
// (ranks_per_material > 1) a material goes to a team; its leader writes the material's files.

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "twin/base/json_field.h"
#include "twin/batch/batch_manifest.h"
#include "twin/distributed/rank_group.h"

namespace twin::batch {

struct BatchRow {
  std::string name;
  std::string status;   // "done" (this run), "already done" (an earlier run's), "failed"
  std::string verdict;  // diagnosis verdict ("effect", "none", "unexplained", "model_form")
  std::string effect;   // named effect, "" when none
  double held_out_before_mm = 0.0;  // mean correspondence error of the base fit on the held-out trials
  double held_out_after_mm = 0.0;   // with the named effect (or the closest candidate); 0 when none
  double noise_sigma_mm = 0.0;
  double seconds = 0.0;             // of the run that made it
  std::string error;                // "failed": what went wrong
  std::string note;                 // e.g. that an earlier run stopped while diagnosing it
};

nlohmann::json row_json(const BatchRow& row);
// Throws std::invalid_argument naming the source and the field missing or of another type.
BatchRow row_from_field(const JsonField& f);
BatchRow row_from_json(const nlohmann::json& j);

struct BatchOptions {
  std::string out;                                    // OUT
  std::function<void(const std::string&)> progress;   // one line per material, and the diagnosis's
  distributed::RankGroup* ranks = nullptr;            // null: this process alone
  // Ranks per material (`twin batch --ranks-per-material K`): the ranks are split into teams of K;
  // materials are handed out to the teams, and each material's refit searches are spread over its
  // team (diagnose.h). 1: whole materials to single ranks. At most the number of ranks.
  int ranks_per_material = 1;
};

struct BatchResult {
  std::vector<BatchRow> rows;  // manifest order
  int done = 0, already_done = 0, failed = 0;
};

// Throws std::runtime_error only when OUT cannot be written; a material's failure is a row.
// Every rank calls it; the result (rows, counts) is on rank 0, empty on the others.
BatchResult run_batch(const BatchManifest& manifest, const BatchOptions& options);

// The summary table (markdown), as OUT/summary.md holds it.
std::string summary_table(const BatchResult& result);

}  // namespace twin::batch
