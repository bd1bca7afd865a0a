// Descriptor set of the memory update and light transitions (memory_*.comp): one layout for all of them,
// bindings MEMORY_BINDING_* of probebake/bindings.h. Bindings 0-3 carry sample_irradiance.glsl's names.
#ifndef PROBEBAKE_MEMORY_BINDINGS_GLSL
#define PROBEBAKE_MEMORY_BINDINGS_GLSL

#include "probebake/bindings.h"
#include "probebake/memory_types.h"
#include "probebake/runtime_types.h"

layout(std430, binding = MEMORY_BINDING_VOLUME_INFO) readonly buffer VolumeInfoBuffer { VolumeInfo probebake_info; };
layout(std430, binding = MEMORY_BINDING_PROBES) buffer ProbeBuffer { Probe probebake_probes[]; };
layout(std430, binding = MEMORY_BINDING_SVO_NODES) buffer SvoNodeBuffer { int probebake_svo_nodes[]; };
layout(std430, binding = MEMORY_BINDING_SVO_LEAVES) buffer SvoLeafBuffer { SvoLeaf probebake_svo_leaves[]; };
layout(std430, binding = MEMORY_BINDING_OCTREE) buffer OctreeBuffer { int probebake_octree[]; };
layout(std430, binding = MEMORY_BINDING_LIGHTING_INFO) readonly buffer LightingInfoBuffer { LightingInfo probebake_lighting; };
layout(std430, binding = MEMORY_BINDING_RAY_DIRECTIONS) readonly buffer RayDirectionBuffer { vec4 probebake_ray_directions[]; };
layout(std430, binding = MEMORY_BINDING_TRACE_TREES) readonly buffer TraceTreeBuffer { TraceTree probebake_trace_trees[]; };
layout(std430, binding = MEMORY_BINDING_TRACE_NODES) readonly buffer TraceNodeBuffer { TraceNode probebake_trace_nodes[]; };
layout(std430, binding = MEMORY_BINDING_TRACE_FACES) readonly buffer TraceFaceBuffer { TraceFace probebake_trace_faces[]; };
layout(std430, binding = MEMORY_BINDING_TRACE_VERTICES) readonly buffer TraceVertexBuffer { TraceVertex probebake_trace_vertices[]; };
layout(std430, binding = MEMORY_BINDING_TRACE_MATERIALS) readonly buffer TraceMaterialBuffer { TraceMaterial probebake_trace_materials[]; };
layout(std430, binding = MEMORY_BINDING_DYNAMIC_OBJECTS) readonly buffer DynamicObjectBuffer { DynamicObject probebake_dynamic_objects[]; };
layout(std430, binding = MEMORY_BINDING_OBJECT_INSTANCES) readonly buffer ObjectInstanceBuffer { ObjectInstance probebake_object_instances[]; };
layout(std430, binding = MEMORY_BINDING_SURFEL_BATCHES) buffer SurfelBatchBuffer { SurfelBatch surfel_batches[]; };
layout(std430, binding = MEMORY_BINDING_LEAF_HEADER) buffer LeafHeaderBuffer { LeafQueueHeader leaf_header; };
layout(std430, binding = MEMORY_BINDING_LEAF_ENTRIES) buffer LeafEntryBuffer { LeafEntry leaf_entries[]; };
layout(std430, binding = MEMORY_BINDING_KEYS) buffer KeyBuffer { int queue_keys[]; };
layout(std430, binding = MEMORY_BINDING_STATE) buffer StateBuffer { MemoryState memory_state; };
layout(std430, binding = MEMORY_BINDING_CLUSTER_STACK) buffer ClusterStackBuffer { int cluster_stack[]; };
layout(std430, binding = MEMORY_BINDING_PROBE_STACK) buffer ProbeStackBuffer { int probe_stack[]; };
layout(std430, binding = MEMORY_BINDING_BATCH_STACK) buffer BatchStackBuffer { int batch_stack[]; };
layout(std430, binding = MEMORY_BINDING_WORK) buffer WorkBuffer { MemoryWork memory_work[]; };
layout(std430, binding = MEMORY_BINDING_MERGE_SH) buffer MergeShBuffer { float merge_sh[]; };
layout(std430, binding = MEMORY_BINDING_MARKS) buffer MarkBuffer { int node_marks[]; };
layout(std430, binding = MEMORY_BINDING_FRAME) readonly buffer FrameBuffer { MemoryFrame memory_frame; int seat_data[]; };
layout(std430, binding = MEMORY_BINDING_COUNTERS) buffer CounterBuffer { MemoryCounters memory_counters; };
layout(std430, binding = MEMORY_BINDING_TRACE_FLAGS) buffer TraceFlagBuffer { uint trace_flags[]; };
layout(std430, binding = MEMORY_BINDING_PROBE_GENERATIONS) buffer ProbeGenerationBuffer { uint probe_generations[]; };
layout(std430, binding = MEMORY_BINDING_SVO_GENERATIONS) buffer SvoGenerationBuffer { uvec4 svo_generations[]; };
layout(std430, binding = MEMORY_BINDING_SVO_BAKE) readonly buffer SvoBakeBuffer { ivec4 svo_bake[]; }; // int bits: keys are not floats
layout(std430, binding = MEMORY_BINDING_LIGHT_LIST) buffer LightListBuffer { LightListHeader light_list_header; int light_list[]; };

#define PROBEBAKE_DECLARE_BUFFERS 0

#endif // PROBEBAKE_MEMORY_BINDINGS_GLSL
