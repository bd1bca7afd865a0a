// `probebake info FILE.probes`: sections and bytes, counts, depth histogram, cells and settings of a
// baked file. Called by the info command when the file is a .probes file.
#pragma once

#include <string>

namespace probebake::cli {

// Prints a description of the .probes file (text, or one JSON object with keys including "probes",
// "nodes", "max_depth", "sections", "cells"). Returns the exit code (0); throws probebake::Error(input)
// when the file cannot be read or decoded. Checksum mismatches are reported as warnings on stderr.
int run_info_probes(const std::string& path, bool json);

} // namespace probebake::cli
