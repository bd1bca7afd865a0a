// Probe index build, dispatch 2 of 3: one workgroup turns block_sums into exclusive offsets in place,
// PROBE_INDEX_THREADS blocks per step with a running carry, and stores the live probe count. (A single
// workgroup is enough: even 2^20 blocks of 1024 probes are 8192 cheap steps.)
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probe_index/probe_index.glsl"

void main() {
  uint carry = 0u;
  for (uint first = 0u; first < push.block_count; first += PROBE_INDEX_THREADS) {
    const uint block = first + gl_LocalInvocationIndex;
    const uint count = block < push.block_count ? block_sums[block] : 0u;
    uint total;
    const uint offset = workgroup_exclusive_scan(count, total);
    if (block < push.block_count) block_sums[block] = carry + offset;
    carry += total;
  }
  if (gl_LocalInvocationIndex == 0u) counters.live_probes = int(carry);
}
