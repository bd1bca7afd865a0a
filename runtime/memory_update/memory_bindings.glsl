// The memory update's and light transitions' bindings (memory_*.comp): the volume set, whose tree they
// reshape (volume_bindings.glsl, PROBEBAKE_WRITES_TREE), and the pass's own buffers in set 1
// (memory_update_bindings.h).
#ifndef PROBEBAKE_MEMORY_BINDINGS_GLSL
#define PROBEBAKE_MEMORY_BINDINGS_GLSL

#define PROBEBAKE_WRITES_TREE
#include "probebake/volume_bindings.glsl"
#include "probebake/memory_types.h"
#include "memory_update/memory_update_bindings.h"

#define PROBEBAKE_MEMORY_BUFFER(index) layout(std430, set = PASS_SET, binding = index) buffer
// clang-format off
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_STATE) StateBuffer { MemoryState memory_state; int queue_keys[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_FREE_STACKS) FreeStackBuffer { int free_stacks[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_WORK) WorkBuffer { MemoryWork memory_work[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_MERGE_SH) MergeShBuffer { float merge_sh[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_MARKS) MarkBuffer { int node_marks[]; };
layout(std430, set = PASS_SET, binding = MEMORY_BINDING_FRAME) readonly buffer FrameBuffer { MemoryFrame memory_frame; int seat_data[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_COUNTERS) CounterBuffer { MemoryCounters memory_counters; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_TRACE_FLAGS) TraceFlagBuffer { uint trace_flags[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_PROBE_GENERATIONS) ProbeGenerationBuffer { uint probe_generations[]; };
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_SVO_GENERATIONS) SvoGenerationBuffer { uvec4 svo_generations[]; };
layout(std430, set = PASS_SET, binding = MEMORY_BINDING_SVO_BAKE) readonly buffer SvoBakeBuffer { ivec4 svo_bake[]; }; // int bits: keys are not floats
PROBEBAKE_MEMORY_BUFFER(MEMORY_BINDING_LIGHT_LIST) LightListBuffer { LightListHeader light_list_header; int light_list[]; };
// clang-format on

// The three free-list stacks share one buffer (a binding fewer: a kernel may see 32 storage buffers on
// lavapipe): clusters (meta indices) from 0, probe slots from probe_stack_base, surfel batches from
// batch_stack_base.
#define cluster_stack_at(i) free_stacks[(i)]
#define probe_stack_at(i) free_stacks[memory_state.probe_stack_base + (i)]
#define batch_stack_at(i) free_stacks[memory_state.batch_stack_base + (i)]

#endif // PROBEBAKE_MEMORY_BINDINGS_GLSL
