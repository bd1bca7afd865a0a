// Memory update, allocate (one thread per pulled entry): M1 seats a probe from its granted stack range, M3
// splits the leaf (a granted cluster; the parent's probe and surfel chain move to the first child, seven
// granted probes seat the others, all starting from the parent's irradiance); deferred, dry and stale
// entries are pushed back as TreeUpdate pushes them. Only pops (granted ranges) and queue pushes.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void allocate_probe(MemoryWork w) {
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(w.node, cube_min, size, depth);
  const int probe = probe_stack_at(w.probe_first);
  seat_probe(probe, w.node, cube_min, size, depth);
  give_surfel_chain(probe, w.batch_first);
  initial_irradiance(probe, cube_min + vec3(0.5 * size));
  atomicAdd(memory_counters.probes_placed, 1);
  queue_push(memory_light_out(), w.node, LEAF_L1_PLACE_SURFELS);
}

void split(MemoryWork w) {
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(w.node, cube_min, size, depth);
  const int parent_probe = ~probebake_octree[w.node];
  const int meta = cluster_stack_at(w.cluster_first);
  probebake_octree[meta] = ~w.node; // its eight nodes are zero: leaves without probes
  probebake_octree[w.node] = meta;
  const float half_size = 0.5 * size;
  for (int o = 0; o < 8; ++o) {
    const int child = meta + 1 + o;
    precise const vec3 child_min = cube_min + vec3(float(o & 1), float((o >> 1) & 1), float((o >> 2) & 1)) * half_size;
    const int probe = o == 0 ? parent_probe : probe_stack_at(w.probe_first + o - 1);
    seat_probe(probe, child, child_min, half_size, depth + 1);
    if (o == 0) {
      clear_surfel_chain(probe);
    } else {
      give_surfel_chain(probe, w.batch_first + (o - 1) * memory_frame.batches_per_probe);
      for (int k = 0; k < PROBE_SH_FLOATS; ++k) probebake_probes[probe].irradiance_sh[k] = probebake_probes[parent_probe].irradiance_sh[k];
    }
    queue_push(memory_light_out(), child, LEAF_L1_PLACE_SURFELS);
  }
  atomicAdd(memory_counters.splits, 1);
}

void main() {
  const int i = memory_item(memory_state.memory_pulled);
  if (i < 0) return;
  const MemoryWork w = memory_work[i];
  if (w.action == MEMORY_ACTION_ALLOCATE_PROBE) {
    allocate_probe(w);
  } else if (w.action == MEMORY_ACTION_SPLIT) {
    split(w);
  } else if (w.action == MEMORY_ACTION_DEFER) {
    // Keeps its state and holds its parent in M0; both end in a fresh L1 measurement.
    queue_push(memory_memory_out(), w.node, w.state);
    queue_push_parent(memory_memory_out(), w.node, LEAF_M0_CHILD_ALLOCATING);
  } else if (w.action == MEMORY_ACTION_DRY && w.state == LEAF_M1_ALLOCATE_PROBE) {
    queue_push(memory_light_out(), w.node, LEAF_L3_CHECK_BOXES);
    // Its M0 may have hidden a sibling's request to free the cluster: ask again.
    queue_push_parent(memory_memory_out(), w.node, LEAF_M4_FREE_CLUSTER);
  } else if (w.action == MEMORY_ACTION_DRY || w.action == MEMORY_ACTION_SPLIT_AT_MAX) {
    queue_push(memory_light_out(), w.node, LEAF_L1_PLACE_SURFELS); // measured again next frame
  }
}
