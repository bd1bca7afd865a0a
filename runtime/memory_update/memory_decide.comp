// Memory update, decide (one thread per pulled entry): reads the entry's node and the state its key holds,
// drops stale entries, and judges M4 parents on the tree as the frame found it: a parent whose children are
// all leaves merges them when its own centre, measured now, would not split it (TreeUpdate::collapse_verdict).
// M2 leaves are marked so that a merging parent leaves their probes to them. Nothing is allocated or freed.
// One workgroup per entry: the lattice of a merging parent is cast by the whole group. Streaming: a parent
// whose lattice crosses a cell that is out does not merge (its measure misses that cell's geometry); it is
// marked to be judged again when cells arrive (memory_remeasure).
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_NULL_LEAF memory_frame.null_leaf // streaming: lattice rays that cross a cell that is out
#define PROBEBAKE_OCTREE_GROUP_MEASURE MEMORY_WORKGROUP_SIZE
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

shared LeafEntry entry;

// Whether M4 parent `node` has only leaves as children (it may merge; its centre is measured).
bool may_merge(LeafEntry e) {
  if (e.state != LEAF_M4_FREE_CLUSTER || !node_fits_state(e.node, e.state)) return false;
  const int meta = probebake_octree[e.node];
  for (int o = 0; o < 8; ++o)
    if (probebake_octree[meta + 1 + o] > 0) return false;
  return true;
}

void main() {
  const int i = int(probebake_flat_workgroup());
  if (i >= memory_state.memory_pulled) return; // uniform per workgroup
  if (gl_LocalInvocationIndex == 0) entry = queue_take(memory_state.memory_segment, i);
  barrier();
  const LeafEntry e = entry;
  // M4: merge unless the parent's own centre, measured now, would split it (TreeUpdate::collapse_verdict).
  int verdict = -1;
  bool unresolved = false;
  if (may_merge(e)) {
    vec3 cube_min;
    float size;
    int depth;
    octree_node_cube(e.node, cube_min, size, depth);
    const vec2 m = octree_measure_group(cube_min, size);
    verdict = leaf_verdict(m.x, m.y, depth, probebake_info, memory_frame.dead_backface_fraction);
    unresolved = octree_measure_unresolved;
  }
  if (gl_LocalInvocationIndex != 0) return;
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
  } else if (e.state == LEAF_M4_FREE_CLUSTER && unresolved) {
    node_marks[e.node] = MEMORY_MARK_REMEASURE;
    atomicAdd(memory_counters.unresolved_measures, 1);
  } else if (e.state == LEAF_M4_FREE_CLUSTER) {
    if (verdict >= 0 && verdict != LEAF_VERDICT_SPLIT) {
      w.action = MEMORY_ACTION_COLLAPSE;
      w.verdict = verdict;
      node_marks[e.node] = 1 + verdict;
    }
  }
  memory_work[i] = w;
}
