#pragma once
// Plain-text point files, as the scanner, the manifest tools and extract_markers exchange them:
// one "x y z" line per point (metres), blank lines and lines starting with '#' skipped.
// "nan nan nan" marks a point that is not known (a marker not seen, a guide with no guess) and
// is accepted only where the caller allows it; a line with only some components NaN, infinite
// values, or anything other than three numbers is an error naming file:line.

#include <istream>
#include <string>
#include <vector>

#include "tracking/types.h"

namespace tracking {

// Parses `in`; `source_name` is the file name used in error messages. Throws
// std::invalid_argument("<source_name>:<line>: ...").
std::vector<Vec3> parse_xyz(std::istream& in, const std::string& source_name, bool allow_nan);

// Reads a file with parse_xyz. Throws std::invalid_argument for bad content and for a file that
// cannot be opened (the message names the path).
std::vector<Vec3> read_xyz_file(const std::string& path, bool allow_nan);

// Writes one line per point ("nan nan nan" for unknown points) with enough digits to read back
// the same doubles, after an optional '#' comment header (one comment line per '\n'-separated
// line of `header`). Written durably (common/durable_file.h): a reader or a crash never finds a
// half-written file and an existing file survives a failed write. Throws std::runtime_error
// naming the path.
void write_xyz_file(const std::string& path, const std::vector<Vec3>& points,
                    const std::string& header = "");

}  // namespace tracking
