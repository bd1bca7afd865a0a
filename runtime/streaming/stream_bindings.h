// Set 1 of the streamed tracing arena's compaction (stream_relocate.comp); it reads nothing of the volume set.
#ifndef PROBEBAKE_STREAM_BINDINGS_H
#define PROBEBAKE_STREAM_BINDINGS_H

#include "probebake/bindings.h"

PB_GPU_BEGIN

PB_CONSTANT(uint, STREAM_BINDING_ARENA, 0u);   // the streamed tracing arena (uint words)
PB_CONSTANT(uint, STREAM_BINDING_SCRATCH, 1u); // a copy of the block being moved, from word 0
PB_CONSTANT(uint, STREAM_BINDING_COUNT, 2u);

PB_GPU_END
#endif // PROBEBAKE_STREAM_BINDINGS_H
