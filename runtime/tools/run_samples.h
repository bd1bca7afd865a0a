// probebake-run --samples: times the runtime's irradiance lookups on random points of the volume.
#pragma once

#include "probebake/runtime/runtime.h"

namespace probebake::run {

// The SVO sampler, the grid engine's on a grid bake with a lattice, and with `compare` the all-probe baseline on
// `count` random points of the root cube (fixed seed): a line per sampler, the time ratio and the relative
// RMS of the difference over the RMS of the baseline.
runtime::Status run_samples(runtime::Volume& volume, int count, bool compare);

} // namespace probebake::run
