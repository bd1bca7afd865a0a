// Memory update, streaming cells (one thread per cell change of the frame, after collapse): the probe tree
// follows the cells' residency through the pools the memory update allocates from.
//  - A cell that drops gives its subtree back: every probe but one (with its surfel batches) onto the probe
//    stack, every cluster onto the cluster stack. The cell's node becomes a leaf whose probe holds the mean
//    irradiance of the probes it replaced: the sampler's answer there until the cell returns, flagged not lit
//    (the probe lies inside the cell that is out: light_trace leaves it unresolved).
//  - A cell that arrives has its node measured again (L1; a probe-less leaf asks for a probe, M1): the
//    memory update then grows the subtree that the cell's geometry asks for, a level a frame, from the pools.
// A cell whose node is inside a larger leaf (the tree is coarser there) shares that leaf: a drop leaves it,
// an arrival measures it. Only pushes onto the stacks, as memory_release.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/memory_bindings.glsl"
#include "probebake/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

// The node of cell `cell` (grid index at memory_frame.cell_depth), or the leaf above it that holds it.
int cell_node(uint cell) {
  const int depth = memory_frame.cell_depth;
  const uint n = 1u << uint(depth);
  const uint x = cell % n, y = cell / n % n, z = cell / (n * n);
  int node = 0;
  for (int level = 0; level < depth; ++level) {
    const int meta = probebake_octree[node];
    if (meta <= 0) break; // a leaf
    const uint bit = uint(depth - 1 - level);
    node = meta + 1 + int(((x >> bit) & 1u) | (((y >> bit) & 1u) << 1) | (((z >> bit) & 1u) << 2));
  }
  return node;
}

// Frees the subtree below `root` (an inner node): its probes but `kept` (the first found, returned) and
// their surfel batches, its clusters; `mean` gets the sum of the probes' irradiance, `count` their number.
int free_subtree(int root, inout float mean[27], inout int count) {
  int kept = -1;
  // The clusters still to visit (their meta index: a cluster is zeroed as it is visited, the words of its
  // inner nodes with it): at most 7 siblings waiting per level, and one.
  int stack[8 * OCTREE_MAX_DEPTH];
  int top = 0;
  stack[top++] = probebake_octree[root];
  while (top > 0) {
    const int meta = stack[--top];
    for (int o = 0; o < 8; ++o) {
      const int child = meta + 1 + o;
      const int v = probebake_octree[child];
      node_marks[child] = 0;
      if (v > 0 && top < 8 * OCTREE_MAX_DEPTH) {
        stack[top++] = v;
        continue;
      }
      if (v >= 0) continue;
      const int probe = ~v;
      for (int k = 0; k < 27; ++k) mean[k] += probebake_probes[probe].irradiance_sh[k];
      ++count;
      if (kept < 0) {
        kept = probe;
        atomicAdd(probe_generations[probe], 1u); // it moves: the SVO stops reading it
      } else {
        release_probe(probe);
        atomicAdd(memory_counters.probes_freed, 1);
      }
    }
    for (int k = 0; k < OCTREE_CLUSTER_SIZE; ++k) probebake_octree[meta + k] = 0;
    push_free_cluster(meta);
  }
  return kept;
}

void drop(uint cell) {
  const int node = cell_node(cell);
  if (probebake_octree[node] <= 0) return; // a leaf: nothing below it to give back
  float mean[27];
  for (int k = 0; k < 27; ++k) mean[k] = 0.0;
  int count = 0;
  const int kept = free_subtree(node, mean, count);
  probebake_octree[node] = 0;
  node_marks[node] = 0;
  atomicAdd(memory_counters.cells_collapsed, 1);
  if (kept < 0) { // no probe below: a probe-less leaf
    queue_push(memory_light_out(), node, LEAF_L3_CHECK_BOXES);
    return;
  }
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(node, cube_min, size, depth);
  seat_probe(kept, node, cube_min, size, depth);
  clear_surfel_chain(kept);
  for (int k = 0; k < 27; ++k) probebake_probes[kept].irradiance_sh[k] = mean[k] / float(count);
  queue_push(memory_light_out(), node, LEAF_L2_LIGHT);
}

void arrive(uint cell) {
  const int node = cell_node(cell);
  const int v = probebake_octree[node];
  if (v < 0) {
    queue_push(memory_light_out(), node, LEAF_L1_PLACE_SURFELS);
  } else if (v == 0) {
    queue_push(memory_memory_out(), node, LEAF_M1_ALLOCATE_PROBE);
    queue_push_parent(memory_memory_out(), node, LEAF_M0_CHILD_ALLOCATING);
  }
}

void main() {
  const int i = memory_item(memory_frame.cell_changes);
  if (i < 0) return;
  const uint entry = memory_frame.cells[i];
  if ((entry & MEMORY_CELL_ARRIVED) != 0u) arrive(entry & ~MEMORY_CELL_ARRIVED);
  else drop(entry);
}
