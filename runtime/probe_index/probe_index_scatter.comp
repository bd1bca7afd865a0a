// Probe index build, dispatch 3 of 3: each allocated probe writes its index at its block's offset plus its
// rank inside the block. The list was reset to PROBE_INDEX_END (vkCmdFillBuffer) before dispatch 1.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probe_index/probe_index.glsl"

void main() {
  const uint block = probebake_flat_workgroup();
  if (block >= push.block_count) return;
  const uint first = first_probe_of_thread(block);
  uint count = 0u;
  for (uint k = 0u; k < PROBE_INDEX_PER_THREAD; ++k) count += probe_allocated(first + k);
  uint total;
  uint slot = block_sums[block] + workgroup_exclusive_scan(count, total);
  for (uint k = 0u; k < PROBE_INDEX_PER_THREAD; ++k) {
    if (probe_allocated(first + k) == 0u) continue;
    probe_index[slot] = int(first + k);
    ++slot;
  }
}
