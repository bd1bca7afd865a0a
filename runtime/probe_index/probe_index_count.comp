// Probe index build, dispatch 1 of 3 (octree thesis §3.2.3): block_sums[b] = allocated probes in block b.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probe_index/probe_index.glsl"

void main() {
  const uint block = probebake_flat_workgroup();
  if (block >= push.block_count) return; // uniform per workgroup: the whole group leaves together
  const uint first = first_probe_of_thread(block);
  uint count = 0u;
  for (uint k = 0u; k < PROBE_INDEX_PER_THREAD; ++k) count += probe_allocated(first + k);
  uint total;
  workgroup_exclusive_scan(count, total);
  if (gl_LocalInvocationIndex == 0u) block_sums[block] = total;
}
