// Memory update, decide (one thread per pulled entry): reads the entry's node and the state its key holds,
// drops stale entries, and judges M4 parents on the tree as the frame found it: a parent whose children are
// all leaves merges them when its own centre, measured now, would not split it (TreeUpdate::collapse_verdict).
// M2 leaves are marked so that a merging parent leaves their probes to them. Nothing is allocated or freed.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/memory_bindings.glsl"
#include "probebake/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

// LEAF_VERDICT_* of merging parent `node`, or -1 when it stays a parent.
int merge_verdict(int node) {
  const int meta = probebake_octree[node];
  for (int o = 0; o < 8; ++o)
    if (probebake_octree[meta + 1 + o] > 0) return -1;
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(node, cube_min, size, depth);
  const vec2 m = octree_measure(cube_min, size);
  const int verdict = leaf_verdict(m.x, m.y, depth, probebake_info, memory_frame.dead_backface_fraction);
  return verdict == LEAF_VERDICT_SPLIT ? -1 : verdict;
}

void main() {
  const int i = memory_item(memory_state.memory_pulled);
  if (i < 0) return;
  const LeafEntry e = queue_take(memory_state.memory_segment, i);
  MemoryWork w = MemoryWork(e.node, e.state, MEMORY_ACTION_NONE, 0, -1, 0, 0, 0, 0, 0, 0, 0);
  if (e.state < 0 || !node_fits_state(e.node, e.state)) {
    w.action = MEMORY_ACTION_STALE;
  } else if (e.state == LEAF_M1_ALLOCATE_PROBE) {
    w.action = MEMORY_ACTION_ALLOCATE_PROBE;
  } else if (e.state == LEAF_M2_FREE_PROBE) {
    w.action = MEMORY_ACTION_FREE_PROBE;
    node_marks[e.node] = MEMORY_MARK_FREEING;
  } else if (e.state == LEAF_M3_SPLIT) {
    w.action = MEMORY_ACTION_SPLIT;
  } else if (e.state == LEAF_M4_FREE_CLUSTER) {
    const int verdict = merge_verdict(e.node);
    if (verdict >= 0) {
      w.action = MEMORY_ACTION_COLLAPSE;
      w.verdict = verdict;
      node_marks[e.node] = 1 + verdict;
    }
  }
  memory_work[i] = w;
}
