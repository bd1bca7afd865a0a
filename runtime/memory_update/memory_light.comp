// Light update, state transitions L0-L3 (octree thesis §3.2.2 with dynamic/tree_update.h's departures; one
// thread per entry the light update pulled, after the probe index build). A leaf whose cube a changed box
// touches is re-measured: without a probe it asks for one (M1, parent M0); with one it goes to L1, which
// casts the placement lattice from its centre and acts on the leaf rule (leaf_rule.h): M2, M3 (parent M0),
// or L2 (parent M4: the change may have made the parent's split unnecessary). L1/L2 leaves over the
// per-frame limit wait, a touched one as L1. Kept L1 probes are flagged for light_trace's records; every
// processed L1/L2 probe goes on the light list that trace, gather and resolve walk. One workgroup per
// entry: invocation 0 decides, the whole group casts an L1 lattice. Streaming: a lattice that crosses a cell
// that is out misses its geometry, so the leaf keeps its shape and its probe (L2) and is marked to be
// measured again when cells arrive (memory_remeasure). For the same reason a probe-less leaf that a box
// touches is measured first while cells are out, and asks for a probe (M1) only when its measure sees every
// cell it reaches; otherwise it stays L3, marked.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_NULL_LEAF memory_frame.null_leaf // streaming: lattice rays that cross a cell that is out
#define PROBEBAKE_OCTREE_GROUP_MEASURE MEMORY_WORKGROUP_SIZE
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

shared int measure_node; // the L1 leaf the group measures, -1 = none
shared vec4 measure_cube; // its cube: min, size
shared int measure_depth;

// Invocation 0: the entry's transition up to L1's measure; returns whether the leaf is to be measured.
bool transition(int i) {
  const LeafEntry e = queue_take(memory_state.light_segment, i);
  if (e.state == LEAF_L0_PARENT_FREED) { atomicAdd(memory_counters.processed[e.state], 1); return false; }
  if (e.state < 0 || !node_fits_state(e.node, e.state)) { atomicAdd(memory_counters.stale_entries, 1); return false; }
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
    return false;
  }
  atomicAdd(memory_counters.processed[e.state], 1);
  if (v == 0) { // L3: only the boxes
    if (moved && memory_frame.null_leaf != 0u) { // streaming: M1 waits for a measure that sees every cell
      measure_node = e.node;
      measure_cube = vec4(cube_min, size);
      measure_depth = depth;
      return true;
    }
    if (moved) {
      queue_push(memory_out, e.node, LEAF_M1_ALLOCATE_PROBE);
      queue_push_parent(memory_out, e.node, LEAF_M0_CHILD_ALLOCATING);
    } else {
      queue_push(light_out, e.node, LEAF_L3_CHECK_BOXES);
    }
    return false;
  }
  light_list[atomicAdd(light_list_header.count, 1u)] = ~v; // L1 and L2 light the probe this frame
  if (e.state == LEAF_L2_LIGHT && !moved) { queue_push(light_out, e.node, LEAF_L2_LIGHT); return false; }
  measure_node = e.node;
  measure_cube = vec4(cube_min, size);
  measure_depth = depth;
  return true;
}

// Invocation 0: L1 acts on the measure of the leaf in the current pose.
void act(int node, vec2 m, int depth) {
  const int v = probebake_octree[node];
  if (octree_measure_unresolved) {
    queue_push(light_light_out(), node, v == 0 ? LEAF_L3_CHECK_BOXES : LEAF_L2_LIGHT);
    node_marks[node] = MEMORY_MARK_REMEASURE;
    atomicAdd(memory_counters.unresolved_measures, 1);
    return;
  }
  if (v == 0) { // streaming, a probe-less leaf whose measure resolved: M1 as without streaming
    queue_push(light_memory_out(), node, LEAF_M1_ALLOCATE_PROBE);
    queue_push_parent(light_memory_out(), node, LEAF_M0_CHILD_ALLOCATING);
    return;
  }
  const int probe = ~v;
  probebake_probes[probe].hit_fraction = m.x;
  probebake_probes[probe].backface_fraction = m.y;
  const int verdict = leaf_verdict(m.x, m.y, depth, probebake_info, memory_frame.dead_backface_fraction);
  if (verdict == LEAF_VERDICT_FREE) {
    queue_push(light_memory_out(), node, LEAF_M2_FREE_PROBE);
  } else if (verdict == LEAF_VERDICT_SPLIT) {
    queue_push(light_memory_out(), node, LEAF_M3_SPLIT);
    queue_push_parent(light_memory_out(), node, LEAF_M0_CHILD_ALLOCATING);
  } else {
    queue_push(light_light_out(), node, LEAF_L2_LIGHT);
    queue_push_parent(light_memory_out(), node, LEAF_M4_FREE_CLUSTER);
    trace_flags[probe] = TRACE_FLAG_RETRACE;
  }
}

void main() {
  const int i = int(probebake_flat_workgroup());
  if (i >= memory_state.light_pulled) return; // uniform per workgroup
  if (gl_LocalInvocationIndex == 0) {
    measure_node = -1;
    transition(i);
  }
  barrier();
  const int node = measure_node;
  if (node < 0) return; // uniform
  const vec2 m = octree_measure_group(measure_cube.xyz, measure_cube.w);
  if (gl_LocalInvocationIndex == 0) act(node, m, measure_depth);
}
