// Memory update, collapse (one thread per pulled entry, after the allocations): a merging parent frees its
// child cluster onto the cluster stack (after this frame's splits took theirs, so no new child shares a node
// index with the L0 entries that retire the old ones), becomes a leaf, and stays lit (a kept child probe or
// a granted one, starting from the children's mean irradiance) or probe-less. Clears the frame's marks.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void collapse(int i, MemoryWork w) {
  const int meta = probebake_octree[w.node];
  for (int k = 0; k < OCTREE_CLUSTER_SIZE; ++k) probebake_octree[meta + k] = 0;
  push_free_cluster(meta);
  probebake_octree[w.node] = 0;
  atomicAdd(memory_counters.collapses, 1);
  queue_push_parent(memory_memory_out(), w.node, LEAF_M4_FREE_CLUSTER);
  if (w.verdict != LEAF_VERDICT_KEEP) { // (a kept child probe implies KEEP: memory_grant turns only merges without one)
    queue_push(memory_light_out(), w.node, LEAF_L3_CHECK_BOXES);
    return;
  }
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(w.node, cube_min, size, depth);
  const int probe = w.reuse_probe >= 0 ? w.reuse_probe : probe_stack_at(w.probe_first);
  seat_probe(probe, w.node, cube_min, size, depth);
  if (w.reuse_probe >= 0) clear_surfel_chain(probe);
  else give_surfel_chain(probe, w.batch_first);
  if (w.merged > 0) {
    for (int k = 0; k < PROBE_SH_FLOATS; ++k) probebake_probes[probe].irradiance_sh[k] = merge_sh[PROBE_SH_FLOATS * i + k] / float(w.merged);
  } else {
    initial_irradiance(probe, cube_min + vec3(0.5 * size));
  }
  atomicAdd(memory_counters.probes_placed, 1);
  queue_push(memory_light_out(), w.node, LEAF_L1_PLACE_SURFELS);
}

void main() {
  const int i = memory_item(memory_state.memory_pulled);
  if (i < 0) return;
  const MemoryWork w = memory_work[i];
  if (w.action == MEMORY_ACTION_COLLAPSE) collapse(i, w);
  if (w.action == MEMORY_ACTION_COLLAPSE || w.action == MEMORY_ACTION_FREE_PROBE) node_marks[w.node] = 0;
}
