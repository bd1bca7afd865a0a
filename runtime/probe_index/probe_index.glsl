// Shared code of the probe index build (octree thesis §3.2.3): bindings, push constants and a workgroup
// prefix sum. The build is a deterministic stream compaction of the probes with link != 0: per-block counts,
// one exclusive scan over the blocks, then each probe writes its index at block offset + rank in block, so
// the list comes out in ascending order without atomics (equal to formats::rebuild_probe_index).
#ifndef PROBEBAKE_PROBE_INDEX_GLSL
#define PROBEBAKE_PROBE_INDEX_GLSL

#define PROBEBAKE_WRITES_INDEX
#include "probebake/volume_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probe_index/probe_index_bindings.h"

layout(local_size_x = PROBE_INDEX_THREADS) in;

layout(std430, set = PASS_SET, binding = PROBE_INDEX_BINDING_BLOCK_SUMS) buffer BlockSums { uint block_sums[]; };
layout(std430, set = PASS_SET, binding = PROBE_INDEX_BINDING_COUNTERS) writeonly buffer Counters { RuntimeCounters counters; };
layout(push_constant) uniform Push { ProbeIndexPush push; };

shared uint scan_values[2][PROBE_INDEX_THREADS];

// Exclusive prefix sum of `value` over the workgroup (Hillis-Steele, double-buffered: one barrier per
// step); `total` receives the sum of all. Every invocation of the workgroup must call it.
uint workgroup_exclusive_scan(uint value, out uint total) {
  const uint i = gl_LocalInvocationIndex;
  uint source = 0u;
  scan_values[0][i] = value;
  barrier();
  for (uint offset = 1u; offset < PROBE_INDEX_THREADS; offset <<= 1u) {
    const uint sum = scan_values[source][i] + (i >= offset ? scan_values[source][i - offset] : 0u);
    scan_values[1u - source][i] = sum;
    source = 1u - source;
    barrier();
  }
  total = scan_values[source][PROBE_INDEX_THREADS - 1u];
  const uint inclusive = scan_values[source][i];
  barrier(); // the next call overwrites scan_values[0]
  return inclusive - value;
}

// 1 when probe `index` exists and is allocated.
uint probe_allocated(uint index) {
  return index < push.probe_capacity && probebake_probes[index].link != 0 ? 1u : 0u;
}

// First of the PROBE_INDEX_PER_THREAD consecutive probes this invocation handles in block `block`.
uint first_probe_of_thread(uint block) {
  return block * PROBE_INDEX_BLOCK + gl_LocalInvocationIndex * PROBE_INDEX_PER_THREAD;
}

#endif // PROBEBAKE_PROBE_INDEX_GLSL
