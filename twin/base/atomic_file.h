#pragma once
// Every file the twin writes (meshes, material files, trials, reports, summaries, batch state)
// goes through the cell's shared durable writer (common/durable_file.h): written beside, flushed
// to the disk, renamed over the path, the directory flushed; a failed write leaves an existing
// file intact. Throws std::runtime_error naming the path.

#include "common/durable_file.h"

namespace twin {

using prepreg::create_directories_durably;
using prepreg::sync_directory;
using prepreg::write_file_atomically;

}  // namespace twin
