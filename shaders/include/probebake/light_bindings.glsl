// Descriptor set of the light update passes (light_trace, light_gather, light_resolve): one layout for
// all three, bindings in runtime/src/pipelines.h (LightBinding). Bindings 0-3 carry the names of
// sample_irradiance.glsl, so the gather samples the probes through the same code a game uses.
// Define PROBEBAKE_PROBES_WRITABLE before including to write the probe buffer.
#ifndef PROBEBAKE_LIGHT_BINDINGS_GLSL
#define PROBEBAKE_LIGHT_BINDINGS_GLSL

#include "probebake/runtime_types.h"

#ifdef PROBEBAKE_PROBES_WRITABLE
#define PROBEBAKE_PROBES_ACCESS
#else
#define PROBEBAKE_PROBES_ACCESS readonly
#endif

layout(std430, binding = 0) readonly buffer VolumeInfoBuffer { VolumeInfo probebake_info; };
layout(std430, binding = 1) PROBEBAKE_PROBES_ACCESS buffer ProbeBuffer { Probe probebake_probes[]; };
layout(std430, binding = 2) readonly buffer SvoNodeBuffer { int probebake_svo_nodes[]; };
layout(std430, binding = 3) readonly buffer SvoLeafBuffer { SvoLeaf probebake_svo_leaves[]; };
layout(std430, binding = 4) readonly buffer OctreeBuffer { int probebake_octree[]; };
layout(std430, binding = 5) readonly buffer LightingInfoBuffer { LightingInfo probebake_lighting; };
layout(std430, binding = 6) readonly buffer RayDirectionBuffer { vec4 probebake_ray_directions[]; };
layout(std430, binding = 7) readonly buffer BvhNodeBuffer { BvhNode probebake_bvh_nodes[]; };
layout(std430, binding = 8) readonly buffer TriangleBuffer { TraceTriangle probebake_trace_triangles[]; };
layout(std430, binding = 9) readonly buffer LightBuffer { PunctualLight probebake_lights[]; };
layout(std430, binding = 10) readonly buffer PatchBuffer { EmitterPatch probebake_emitter_patches[]; };
layout(std430, binding = 11) buffer RecordBuffer { LightRecord light_records[]; };
layout(std430, binding = 12) buffer NextIrradianceBuffer { float next_irradiance[]; }; // 27 per probe slot
layout(std430, binding = 13) buffer CounterBuffer { LightCounters light_counters; };
layout(push_constant) uniform Push { LightPush push; };

#define PROBEBAKE_DECLARE_BUFFERS 0

#endif // PROBEBAKE_LIGHT_BINDINGS_GLSL
