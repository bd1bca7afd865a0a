// Set 1 of the memory update and light transitions (memory_bindings.glsl: memory_*.comp): the pass's own
// buffers. The tree it reshapes (octree, probes, SVO, surfel batches, leaf queue) is the volume set's.
#ifndef PROBEBAKE_MEMORY_UPDATE_BINDINGS_H
#define PROBEBAKE_MEMORY_UPDATE_BINDINGS_H

#include "probebake/bindings.h"

PB_GPU_BEGIN

// MemoryState, then int[3 * segment_capacity]: the leaf queue's keys, of node n in segment s at s * capacity + n
PB_CONSTANT(uint, MEMORY_BINDING_STATE, 0u);
// int: the free-list stacks of cluster meta indices, probe slots and surfel batches (MemoryState's bases)
PB_CONSTANT(uint, MEMORY_BINDING_FREE_STACKS, 1u);
PB_CONSTANT(uint, MEMORY_BINDING_WORK, 2u);              // MemoryWork per pulled memory entry
PB_CONSTANT(uint, MEMORY_BINDING_MERGE_SH, 3u);          // float[PROBE_SH_FLOATS] per pulled memory entry
PB_CONSTANT(uint, MEMORY_BINDING_MARKS, 4u);             // int per octree element: MEMORY_MARK_*
PB_CONSTANT(uint, MEMORY_BINDING_FRAME, 5u);             // MemoryFrame
PB_CONSTANT(uint, MEMORY_BINDING_COUNTERS, 6u);          // MemoryCounters
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_FLAGS, 7u);       // = LIGHT_BINDING_TRACE_FLAGS' buffer
PB_CONSTANT(uint, MEMORY_BINDING_PROBE_GENERATIONS, 8u); // uint per probe slot: +1 each time it is freed
PB_CONSTANT(uint, MEMORY_BINDING_SVO_GENERATIONS, 9u);   // ivec4 per SVO leaf: generation of each stencil probe
// 16 B per SVO leaf (float bits): voxel centre, w = its SVO node; with streaming, then the bake stencils
// (SEAT_STENCIL_VEC4S) (static)
PB_CONSTANT(uint, MEMORY_BINDING_SVO_BAKE, 10u);
PB_CONSTANT(uint, MEMORY_BINDING_LIGHT_LIST, 11u); // = LIGHT_BINDING_LIGHT_LIST's buffer
// 12 + VOLUME_BINDING_COUNT (20) = 32: lavapipe's maxPerStageDescriptorStorageBuffers.
PB_CONSTANT(uint, MEMORY_BINDING_COUNT, 12u);

PB_GPU_END
#endif // PROBEBAKE_MEMORY_UPDATE_BINDINGS_H
