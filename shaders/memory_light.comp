// Light update, state transitions L0-L3 (octree thesis §3.2.2 with dynamic/tree_update.h's departures; one
// thread per entry the light update pulled, after the probe index build). A leaf whose cube a changed box
// touches is re-measured: without a probe it asks for one (M1, parent M0); with one it goes to L1, which
// casts the placement lattice from its centre and acts on the leaf rule (leaf_rule.h): M2, M3 (parent M0),
// or L2 (parent M4: the change may have made the parent's split unnecessary). L1/L2 leaves over the
// per-frame limit wait, a touched one as L1. Kept L1 probes are flagged for light_trace's records; every
// processed L1/L2 probe goes on the light list that trace, gather and resolve walk.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/memory_bindings.glsl"
#include "probebake/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void main() {
  const int i = memory_item(memory_state.light_pulled);
  if (i < 0) return;
  const LeafEntry e = queue_take(memory_state.light_segment, i);
  if (e.state == LEAF_L0_PARENT_FREED) { atomicAdd(memory_counters.processed[e.state], 1); return; }
  if (e.state < 0 || !node_fits_state(e.node, e.state)) { atomicAdd(memory_counters.stale_entries, 1); return; }
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(e.node, cube_min, size, depth);
  const bool moved = cube_touched(cube_min, size);
  const int v = probebake_octree[e.node];
  const int light_out = light_light_out(), memory_out = light_memory_out();
  const int budget = memory_frame.max_light_entries > 0 ? memory_frame.max_light_entries : 0x7fffffff;
  if (v < 0 && atomicAdd(memory_state.traced, 1) >= budget) {
    queue_push(light_out, e.node, moved ? LEAF_L1_PLACE_SURFELS : e.state);
    atomicAdd(memory_counters.deferred, 1);
    return;
  }
  atomicAdd(memory_counters.processed[e.state], 1);
  if (v == 0) { // L3: only the boxes
    if (moved) {
      queue_push(memory_out, e.node, LEAF_M1_ALLOCATE_PROBE);
      queue_push_parent(memory_out, e.node, LEAF_M0_CHILD_ALLOCATING);
    } else {
      queue_push(light_out, e.node, LEAF_L3_CHECK_BOXES);
    }
    return;
  }
  const int probe = ~v;
  light_list[atomicAdd(light_list_header.count, 1u)] = probe; // L1 and L2 light the probe this frame
  if (e.state == LEAF_L2_LIGHT && !moved) { queue_push(light_out, e.node, LEAF_L2_LIGHT); return; }

  // L1: measure the leaf in the current pose and choose its next state.
  const vec2 m = octree_measure(cube_min, size);
  probebake_probes[probe].hit_fraction = m.x;
  probebake_probes[probe].backface_fraction = m.y;
  const int verdict = leaf_verdict(m.x, m.y, depth, probebake_info, memory_frame.dead_backface_fraction);
  if (verdict == LEAF_VERDICT_FREE) {
    queue_push(memory_out, e.node, LEAF_M2_FREE_PROBE);
  } else if (verdict == LEAF_VERDICT_SPLIT) {
    queue_push(memory_out, e.node, LEAF_M3_SPLIT);
    queue_push_parent(memory_out, e.node, LEAF_M0_CHILD_ALLOCATING);
  } else {
    queue_push(light_out, e.node, LEAF_L2_LIGHT);
    queue_push_parent(memory_out, e.node, LEAF_M4_FREE_CLUSTER);
    trace_flags[probe] = 1u;
  }
}
