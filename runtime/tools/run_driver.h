// The run driver: `probebake run FILE.probes` and `probebake-run FILE.probes` (docs/RUNTIME.md).
#pragma once

#include "run_options.h"

namespace probebake::run {

// Runs options.frames frames of the volume in options.input on a Vulkan device, printing the device, the
// volume, one line per frame and a summary to stdout, errors to stderr as "probebake-run: <code>: <message>".
// Returns the exit code: 0 ok, 1 bad argument, 2 bad input file, 3 output not writable, 4 runtime or
// validation failure, 5 the device did not finish a frame within 60 s (StatusCode::too_slow).
int run_volume(const RunOptions& options);

} // namespace probebake::run
