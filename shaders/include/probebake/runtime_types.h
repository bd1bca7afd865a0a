// Structs and constants of the runtime's own compute passes (not stored in .probes files), shared by C++
// and GLSL like gpu_types.h: std430, explicit padding, static_assert on sizes and offsets (C++ side).
#ifndef PROBEBAKE_RUNTIME_TYPES_H
#define PROBEBAKE_RUNTIME_TYPES_H

#include "probebake/gpu_types.h"

#ifdef __cplusplus
namespace probebake::gpu {
#define PB_CONSTANT(type, name, value) inline constexpr type name = value
#else
#define PB_CONSTANT(type, name, value) const type name = value
#endif

// Threads per workgroup of the sampling pass (one query per thread).
PB_CONSTANT(uint, RUNTIME_WORKGROUP_SIZE, 256u);

// ---- Probe index build (octree thesis §3.2.3), three dispatches over blocks of the probe buffer ---------
// Each thread handles PROBE_INDEX_PER_THREAD consecutive elements serially, and the workgroup scans the
// per-thread sums: few barriers per element (barriers are costly on CPU implementations such as lavapipe).
// A block is PROBE_INDEX_BLOCK probes. Scratch buffer: uint[block_count], per-block counts of allocated
// probes, turned in place into exclusive offsets by the scan dispatch (one workgroup, PROBE_INDEX_THREADS
// blocks per step).
PB_CONSTANT(uint, PROBE_INDEX_THREADS, 128u);
PB_CONSTANT(uint, PROBE_INDEX_PER_THREAD, 8u);
PB_CONSTANT(uint, PROBE_INDEX_BLOCK, 1024u); // PROBE_INDEX_THREADS * PROBE_INDEX_PER_THREAD
struct ProbeIndexPush {
  uint probe_capacity; // offset 0: elements in the probe buffer
  uint block_count;    // offset 4: ceil(probe_capacity / PROBE_INDEX_BLOCK)
  uint pad0;           // offset 8
  uint pad1;           // offset 12
};                     // size 16

// Written by the scan dispatch, copied back to the host after each frame.
struct RuntimeCounters {
  int live_probes; // offset  0: allocated probes (link != 0) found by the last probe index build
  int pad0;        // offset  4
  int pad1;        // offset  8
  int pad2;        // offset 12
};                 // size 16

// ---- Irradiance sampling pass (sample_irradiance.comp) ----------------------------------------------------
struct SampleQuery {
  vec3 position; // offset  0: world space, metres
  float pad0;    // offset 12
  vec3 normal;   // offset 16: unit surface normal
  float pad1;    // offset 28
};               // size 32

struct SampleResult {
  vec3 irradiance;  // offset  0: W/m^2, as sample_irradiance (bake/include/probebake/bake/sampler.h)
  int probes_used;  // offset 12: probes in the stencil, 0 = miss
};                  // size 16

struct SamplePush {
  uint count; // offset 0: queries in this dispatch
  uint pad0;  // offset 4
  uint pad1;  // offset 8
  uint pad2;  // offset 12
};            // size 16

#ifdef __cplusplus
static_assert(PROBE_INDEX_BLOCK == PROBE_INDEX_THREADS * PROBE_INDEX_PER_THREAD);
static_assert(sizeof(ProbeIndexPush) == 16 && sizeof(RuntimeCounters) == 16 && sizeof(SamplePush) == 16);
static_assert(sizeof(SampleQuery) == 32 && offsetof(SampleQuery, normal) == 16);
static_assert(sizeof(SampleResult) == 16 && offsetof(SampleResult, probes_used) == 12);
} // namespace probebake::gpu
#endif

#undef PB_CONSTANT
#endif // PROBEBAKE_RUNTIME_TYPES_H
