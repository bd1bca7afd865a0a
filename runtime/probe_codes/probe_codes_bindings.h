// Set 1 of the probe code pass (probe_encode.comp): the points and codes it writes for the lookups. It reads
// the probes of the volume set (probebake/bindings.h).
#ifndef PROBEBAKE_PROBE_CODES_BINDINGS_H
#define PROBEBAKE_PROBE_CODES_BINDINGS_H

#include "probebake/bindings.h"

PB_GPU_BEGIN

PB_CONSTANT(uint, PROBE_CODES_BINDING_POINTS, 0u);
PB_CONSTANT(uint, PROBE_CODES_BINDING_CODES, 1u);
PB_CONSTANT(uint, PROBE_CODES_BINDING_COUNT, 2u);

PB_GPU_END
#endif // PROBEBAKE_PROBE_CODES_BINDINGS_H
