// Memory update, release (one thread per pulled entry): M2 frees its leaf's probe and surfel batches onto
// the free lists; a merging parent frees its children's probes, except the first one, which it keeps for
// itself when it stays lit (no pool traffic), and averages their irradiance for the merged probe. Only
// pushes onto the stacks; memory_grant then hands out what is free.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void free_leaf_probe(MemoryWork w) {
  const int probe = ~probebake_octree[w.node];
  release_probe(probe);
  probebake_octree[w.node] = 0;
  atomicAdd(memory_counters.probes_freed, 1);
  queue_push(memory_light_out(), w.node, LEAF_L3_CHECK_BOXES);
  // Its parent may free the cluster now, unless it does so this very frame.
  if (w.node != 0 && node_marks[octree_parent_of(w.node)] <= 0)
    queue_push_parent(memory_memory_out(), w.node, LEAF_M4_FREE_CLUSTER);
}

void release_children(int i, inout MemoryWork w) {
  const int meta = probebake_octree[w.node];
  for (int k = 0; k < PROBE_SH_FLOATS; ++k) merge_sh[PROBE_SH_FLOATS * i + k] = 0.0;
  for (int o = 0; o < 8; ++o) {
    const int child = meta + 1 + o;
    queue_push(memory_light_out(), child, LEAF_L0_PARENT_FREED);
    const int v = probebake_octree[child];
    if (v >= 0 || node_marks[child] == MEMORY_MARK_FREEING) continue; // no probe, or M2 frees it
    const int probe = ~v;
    for (int k = 0; k < PROBE_SH_FLOATS; ++k) merge_sh[PROBE_SH_FLOATS * i + k] += probebake_probes[probe].irradiance_sh[k];
    w.merged += 1;
    atomicAdd(memory_counters.probes_freed, 1);
    probebake_octree[child] = 0;
    if (w.verdict == LEAF_VERDICT_KEEP && w.reuse_probe < 0) {
      w.reuse_probe = probe;
      atomicAdd(probe_generations[probe], 1u); // it moves: the SVO and initial_irradiance stop reading it
    } else {
      release_probe(probe);
    }
  }
}

void main() {
  const int i = memory_item(memory_state.memory_pulled);
  if (i < 0) return;
  MemoryWork w = memory_work[i];
  if (w.action == MEMORY_ACTION_FREE_PROBE) free_leaf_probe(w);
  else if (w.action == MEMORY_ACTION_COLLAPSE) release_children(i, w);
  memory_work[i] = w;
}
