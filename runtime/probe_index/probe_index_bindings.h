// Set 1 of the probe index build (probe_index.glsl): the pass's own buffers. It reads the probes and writes
// the probe index of the volume set (probebake/bindings.h).
#ifndef PROBEBAKE_PROBE_INDEX_BINDINGS_H
#define PROBEBAKE_PROBE_INDEX_BINDINGS_H

#include "probebake/bindings.h"

PB_GPU_BEGIN

PB_CONSTANT(uint, PROBE_INDEX_BINDING_BLOCK_SUMS, 0u);
PB_CONSTANT(uint, PROBE_INDEX_BINDING_COUNTERS, 1u);
PB_CONSTANT(uint, PROBE_INDEX_BINDING_COUNT, 2u);

PB_GPU_END
#endif // PROBEBAKE_PROBE_INDEX_BINDINGS_H
