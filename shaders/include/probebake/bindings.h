// Descriptor bindings of the volume set: set 0 of every runtime kernel, one storage buffer per section of the
// .probes file that a kernel reads (plus the dynamic objects' poses), written once per volume
// (runtime/core/volume_set.h). The one definition, shared by C++ and GLSL (volume_bindings.glsl) like
// gpu_types.h. Each pass's own buffers are set 1, numbered in its concept folder (runtime/<concept>/*_bindings.h).
// tests/runtime/layout_test.cpp checks each shader's DescriptorSet and Binding decorations against these.
#ifndef PROBEBAKE_BINDINGS_H
#define PROBEBAKE_BINDINGS_H

#include "probebake/gpu_shared.h"

PB_GPU_BEGIN

PB_CONSTANT(uint, VOLUME_SET, 0u);      // the file's sections, shared by every kernel
PB_CONSTANT(uint, PASS_SET, 1u);        // the pass's own buffers
PB_CONSTANT(uint, NO_PASS_BUFFERS, 0u); // set 1 of a layout whose kernels read only the volume set

// 0-3 are the defaults of sample_irradiance.glsl's PROBEBAKE_BINDING_* (what a game binds unless it moves
// them), so a game may bind the runtime's volume set itself.
PB_CONSTANT(uint, VOLUME_BINDING_VOLUME_INFO, 0u);
PB_CONSTANT(uint, VOLUME_BINDING_PROBES, 1u);
PB_CONSTANT(uint, VOLUME_BINDING_SVO_NODES, 2u);
PB_CONSTANT(uint, VOLUME_BINDING_SVO_LEAVES, 3u);
PB_CONSTANT(uint, VOLUME_BINDING_OCTREE, 4u);
PB_CONSTANT(uint, VOLUME_BINDING_PROBE_INDEX, 5u);
PB_CONSTANT(uint, VOLUME_BINDING_SURFEL_BATCHES, 6u);
PB_CONSTANT(uint, VOLUME_BINDING_LEAF_HEADER, 7u);
PB_CONSTANT(uint, VOLUME_BINDING_LEAF_ENTRIES, 8u);
PB_CONSTANT(uint, VOLUME_BINDING_LIGHTING_INFO, 9u);
PB_CONSTANT(uint, VOLUME_BINDING_RAY_DIRECTIONS, 10u);
PB_CONSTANT(uint, VOLUME_BINDING_PUNCTUAL_LIGHTS, 11u);
PB_CONSTANT(uint, VOLUME_BINDING_EMITTER_PATCHES, 12u);
// The compact tracing sections (format 1.4); with streaming, nodes, faces and vertices are the arena's.
PB_CONSTANT(uint, VOLUME_BINDING_TRACE_TREES, 13u);
PB_CONSTANT(uint, VOLUME_BINDING_TRACE_NODES, 14u);
PB_CONSTANT(uint, VOLUME_BINDING_TRACE_FACES, 15u);
PB_CONSTANT(uint, VOLUME_BINDING_TRACE_VERTICES, 16u);
PB_CONSTANT(uint, VOLUME_BINDING_TRACE_MATERIALS, 17u);
PB_CONSTANT(uint, VOLUME_BINDING_DYNAMIC_OBJECTS, 18u);
PB_CONSTANT(uint, VOLUME_BINDING_OBJECT_INSTANCES, 19u); // ObjectInstance per dynamic object (runtime_types.h)
PB_CONSTANT(uint, VOLUME_BINDING_COUNT, 20u);
// An empty section binds a 16-byte placeholder: kernels check the counts in VolumeInfo and never read it.

// A record slot with this bit set belongs to a probe left unresolved: its last trace or relight had a ray
// cross a cell that is out (light_trace.comp). It keeps its irradiance, and a lookup says it is not lit
// (sample_irradiance.glsl). Record slots stay below it.
PB_CONSTANT(int, RECORD_SLOT_UNRESOLVED, 0x40000000);

PB_GPU_END
#endif // PROBEBAKE_BINDINGS_H
