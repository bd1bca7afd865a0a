// The volume set (set 0, VOLUME_BINDING_* of probebake/bindings.h) as every runtime kernel declares it: the
// names sample_irradiance.glsl, bvh_trace.glsl, octree.glsl and direct_light.glsl read. Sections are read
// only unless the kernel defines, before including:
//   PROBEBAKE_WRITES_PROBES     the probes (light_resolve, the memory update);
//   PROBEBAKE_WRITES_TREE       the octree, SVO, surfel batches and leaf queue (the memory update);
//   PROBEBAKE_WRITES_INDEX      the probe index (its build);
//   PROBEBAKE_WRITES_INSTANCES  the dynamic objects' poses (object_refit).
#ifndef PROBEBAKE_VOLUME_BINDINGS_GLSL
#define PROBEBAKE_VOLUME_BINDINGS_GLSL

#include "probebake/bindings.h"
#include "probebake/runtime_types.h"

#ifdef PROBEBAKE_WRITES_TREE
#define PROBEBAKE_WRITES_PROBES
#define PROBEBAKE_TREE_ACCESS
#else
#define PROBEBAKE_TREE_ACCESS readonly
#endif
#ifdef PROBEBAKE_WRITES_PROBES
#define PROBEBAKE_PROBES_ACCESS
#else
#define PROBEBAKE_PROBES_ACCESS readonly
#endif
#ifdef PROBEBAKE_WRITES_INDEX
#define PROBEBAKE_INDEX_ACCESS
#else
#define PROBEBAKE_INDEX_ACCESS readonly
#endif
#ifdef PROBEBAKE_WRITES_INSTANCES
#define PROBEBAKE_INSTANCES_ACCESS
#else
#define PROBEBAKE_INSTANCES_ACCESS readonly
#endif

#define PROBEBAKE_VOLUME_BUFFER(index, access) layout(std430, set = VOLUME_SET, binding = index) access buffer

// clang-format off
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_VOLUME_INFO, readonly) VolumeInfoBuffer { VolumeInfo probebake_info; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_PROBES, PROBEBAKE_PROBES_ACCESS) ProbeBuffer { Probe probebake_probes[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_SVO_NODES, PROBEBAKE_TREE_ACCESS) SvoNodeBuffer { int probebake_svo_nodes[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_SVO_LEAVES, PROBEBAKE_TREE_ACCESS) SvoLeafBuffer { SvoLeaf probebake_svo_leaves[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_OCTREE, PROBEBAKE_TREE_ACCESS) OctreeBuffer { int probebake_octree[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_PROBE_INDEX, PROBEBAKE_INDEX_ACCESS) ProbeIndexBuffer { int probe_index[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_SURFEL_BATCHES, PROBEBAKE_TREE_ACCESS) SurfelBatchBuffer { SurfelBatch surfel_batches[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_LEAF_HEADER, PROBEBAKE_TREE_ACCESS) LeafHeaderBuffer { LeafQueueHeader leaf_header; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_LEAF_ENTRIES, PROBEBAKE_TREE_ACCESS) LeafEntryBuffer { LeafEntry leaf_entries[]; };
// The lighting_info binding carries the sky section's words after LightingInfo (no binding of its own: the light
// layout already uses lavapipe's 32 storage buffers), or four zero words without one (sky.glsl).
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_LIGHTING_INFO, readonly) LightingInfoBuffer { LightingInfo probebake_lighting; uint probebake_sky_words[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_RAY_DIRECTIONS, readonly) RayDirectionBuffer { vec4 probebake_ray_directions[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_PUNCTUAL_LIGHTS, readonly) LightBuffer { PunctualLight probebake_lights[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_EMITTER_PATCHES, readonly) PatchBuffer { EmitterPatch probebake_emitter_patches[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_TRACE_TREES, readonly) TraceTreeBuffer { TraceTree probebake_trace_trees[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_TRACE_NODES, readonly) TraceNodeBuffer { TraceNode probebake_trace_nodes[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_TRACE_FACES, readonly) TraceFaceBuffer { TraceFace probebake_trace_faces[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_TRACE_VERTICES, readonly) TraceVertexBuffer { TraceVertex probebake_trace_vertices[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_TRACE_MATERIALS, readonly) TraceMaterialBuffer { TraceMaterial probebake_trace_materials[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_DYNAMIC_OBJECTS, readonly) DynamicObjectBuffer { DynamicObject probebake_dynamic_objects[]; };
PROBEBAKE_VOLUME_BUFFER(VOLUME_BINDING_OBJECT_INSTANCES, PROBEBAKE_INSTANCES_ACCESS) ObjectInstanceBuffer { ObjectInstance probebake_object_instances[]; };
// clang-format on

// sample_irradiance.glsl reads the names above.
#define PROBEBAKE_DECLARE_BUFFERS 0

#endif // PROBEBAKE_VOLUME_BINDINGS_GLSL
