// Memory update, streaming cells (after collapse): the probe tree follows the cells' residency through the
// pools the memory update allocates from.
//  - push.phase 0, one thread per change: a cell that drops gives its subtree back, every probe but one
//    (with its surfel batches) onto the probe stack, every cluster onto the cluster stack. The cell's node
//    becomes a leaf whose probe holds the mean irradiance of the probes it replaced: the sampler's answer
//    there until the cell returns, flagged not lit (the probe lies inside the cell that is out:
//    light_trace leaves it unresolved). Only pushes onto the stacks.
//  - push.phase 1, one thread for every arrival in turn (only it pops the stacks), then phase 2, a workgroup
//    per arrival: a cell that arrives gets the file's subtree back under its node (CellSeat: clusters,
//    probes and their surfel batches popped from the stacks, the probes as the file has them, lit afresh by
//    light_trace). When the pools lack the room, the seat was too large for the seat data, or the tree is
//    coarser than the cell there, its node is measured again instead (L1; a probe-less leaf asks for a
//    probe, M1) and the memory update grows what the geometry asks for, a level a frame.
//  - push.phase 3, a workgroup per arrival once all are seated: the bake's stencils of the SVO leaves that
//    name the cell's probes come back wherever each of their probes is a leaf with a probe again, in this
//    cell or in a neighbour that is resident.
// A cell whose node is inside a larger leaf shares that leaf: a drop leaves it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;
layout(push_constant) uniform Push { MemoryPush push; };

// The node of cell `cell` (grid index at memory_frame.cell_depth), or the leaf above it that holds it;
// `exact`: the node is the cell's own.
int cell_node(uint cell, out bool exact) {
  const int depth = memory_frame.cell_depth;
  const uint n = 1u << uint(depth);
  const uint x = cell % n, y = cell / n % n, z = cell / (n * n);
  int node = 0;
  exact = true;
  for (int level = 0; level < depth; ++level) {
    const int meta = probebake_octree[node];
    if (meta <= 0) { exact = false; break; } // a leaf
    const uint bit = uint(depth - 1 - level);
    node = meta + 1 + int(((x >> bit) & 1u) | (((y >> bit) & 1u) << 1) | (((z >> bit) & 1u) << 2));
  }
  return node;
}

// Frees the subtree below `root` (an inner node): its probes but `kept` (the first found, returned) and
// their surfel batches, its clusters; `mean` gets the sum of the probes' irradiance, `count` their number.
int free_subtree(int root, inout float mean[PROBE_SH_FLOATS], inout int count) {
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
      for (int k = 0; k < PROBE_SH_FLOATS; ++k) mean[k] += probebake_probes[probe].irradiance_sh[k];
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
  bool exact;
  const int node = cell_node(cell, exact);
  if (probebake_octree[node] <= 0) return; // a leaf: nothing below it to give back
  float mean[PROBE_SH_FLOATS];
  for (int k = 0; k < PROBE_SH_FLOATS; ++k) mean[k] = 0.0;
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
  for (int k = 0; k < PROBE_SH_FLOATS; ++k) probebake_probes[kept].irradiance_sh[k] = mean[k] / float(count);
  queue_push(memory_light_out(), node, LEAF_L2_LIGHT);
}

CellSeat seat_at(uint s) {
  const int i = SEAT_HEADER_INTS * int(s);
  return CellSeat(uint(seat_data[i]), seat_data[i + 1], seat_data[i + 2], seat_data[i + 3], seat_data[i + 4], seat_data[i + 5],
                  seat_data[i + 6], seat_data[i + 7]);
}

// Local probe `l` of the seat as the file has it, made the probe of leaf `node` in slot `probe`.
void seat_file_probe(CellSeat seat, int l, int probe, int node, bool reused, int batch_first) {
  const int at = seat.first_probe + SEAT_PROBE_INTS * l;
  probebake_probes[probe].position = vec3(intBitsToFloat(seat_data[at]), intBitsToFloat(seat_data[at + 1]), intBitsToFloat(seat_data[at + 2]));
  probebake_probes[probe].node = node;
  probebake_probes[probe].depth = seat_data[at + 5];
  probebake_probes[probe].hit_fraction = intBitsToFloat(seat_data[at + 6]);
  probebake_probes[probe].backface_fraction = intBitsToFloat(seat_data[at + 7]);
  for (int k = 0; k < PROBE_SH_FLOATS; ++k) probebake_probes[probe].irradiance_sh[k] = intBitsToFloat(seat_data[at + 8 + k]);
  probebake_probes[probe].pad0 = 0.0;
  if (reused) clear_surfel_chain(probe);
  else give_surfel_chain(probe, batch_first);
  atomicAdd(probe_generations[probe], 1u); // a new probe there: the SVO refills from the tree
  trace_flags[probe] = TRACE_FLAG_RETRACE;
  probebake_octree[node] = ~probe;
  queue_push(memory_light_out(), node, LEAF_L2_LIGHT);
}

// The probe slot of the seat's local probe `l`: the reused mean probe for the first, else popped in order.
int seat_slot(int l, int probe_base, int reused) {
  return l == 0 && reused >= 0 ? reused : probe_stack_at(probe_base + l - (reused >= 0 ? 1 : 0));
}

// The node of a seat word: a cluster's meta index, ~probe slot, or 0 (the caller has popped the ranges).
void seat_node(CellSeat seat, int node, int word, int cluster_base, int probe_base, int batch_base, int reused) {
  if (word > 0) {
    probebake_octree[node] = cluster_stack_at(cluster_base + word - 1);
  } else if (word < 0) {
    const int l = ~word;
    const int batch_first = batch_base + (l - (reused >= 0 ? 1 : 0)) * memory_frame.batches_per_probe;
    seat_file_probe(seat, l, seat_slot(l, probe_base, reused), node, l == 0 && reused >= 0, batch_first);
  } else {
    probebake_octree[node] = 0;
    queue_push(memory_light_out(), node, LEAF_L3_CHECK_BOXES);
  }
  node_marks[node] = 0;
}

// Phase 1, one thread, arrivals in order: pops the ranges of each seat (or measures its node again) and
// leaves them in memory_work[seat] (free after memory_collapse) for phase 2.
void reserve(uint s) {
  const CellSeat seat = seat_at(s);
  memory_work[s] = MemoryWork(-1, 0, MEMORY_ACTION_NONE, 0, -1, 0, 0, 0, 0, 0, 0, 0);
  bool exact;
  const int node = cell_node(seat.cell, exact);
  const int v = probebake_octree[node];
  if (v > 0) return; // its subtree is there (never dropped)
  const int reused = v < 0 ? ~v : -1;
  const int new_probes = max(seat.probes - (reused >= 0 ? 1 : 0), 0);
  const int clusters = max(seat.clusters, 0);
  const int bpp = memory_frame.batches_per_probe;
  const bool room = memory_state.cluster_top >= clusters && memory_state.probe_top >= new_probes &&
                    memory_state.batch_top >= new_probes * bpp;
  if (!exact || !room || seat.clusters < 0) { // clusters < 0: a subtree larger than the seat data
    if (!room && seat.clusters >= 0) memory_counters.failed_allocations += 1;
    queue_measure_again(node); // a leaf: the cell's or the coarser one holding it
    return;
  }
  if (reused >= 0 && seat.probes == 0) { release_probe(reused); probebake_octree[node] = 0; }
  memory_state.cluster_top -= clusters;
  memory_state.probe_top -= new_probes;
  memory_state.batch_top -= new_probes * bpp;
  memory_work[s] = MemoryWork(node, 0, MEMORY_ACTION_SEAT, 0, seat.probes > 0 ? reused : -1, memory_state.cluster_top,
                              memory_state.probe_top, memory_state.batch_top, new_probes, 0, 0, 0);
}

// Phase 2, a workgroup per seat: writes the subtree into the ranges phase 1 popped, a cluster per invocation.
void seat_subtree(uint s) {
  const MemoryWork w = memory_work[s];
  if (w.action != MEMORY_ACTION_SEAT) return;
  const CellSeat seat = seat_at(s);
  if (gl_LocalInvocationIndex == 0) {
    seat_node(seat, w.node, seat.node_word, w.cluster_first, w.probe_first, w.batch_first, w.reuse_probe);
    atomicAdd(memory_counters.probes_placed, w.merged);
  }
  for (int c = int(gl_LocalInvocationIndex); c < seat.clusters; c += int(MEMORY_WORKGROUP_SIZE)) {
    const int at = seat.first_word + OCTREE_CLUSTER_SIZE * c, parent_slot = seat_data[at];
    const int meta = cluster_stack_at(w.cluster_first + c);
    const int parent = parent_slot < 0 ? w.node : cluster_stack_at(w.cluster_first + parent_slot / 8) + 1 + parent_slot % 8;
    probebake_octree[meta] = ~parent;
    for (int o = 0; o < 8; ++o)
      seat_node(seat, meta + 1 + o, seat_data[at + 1 + o], w.cluster_first, w.probe_first, w.batch_first, w.reuse_probe);
  }
}

// The tree's probe at the leaf a key names (SEAT_STENCIL_VEC4S), or -1 when that node is not a leaf with a
// probe now.
int probe_at_key(int xy, int zd) {
  const int depth = zd >> 16;
  if (depth > OCTREE_MAX_DEPTH) return -1;
  int node = 0;
  for (int d = depth - 1; d >= 0; --d) {
    const int v = probebake_octree[node];
    if (v <= 0) return -1;
    const int octant = ((xy >> d) & 1) | (((xy >> (16 + d)) & 1) << 1) | (((zd >> d) & 1) << 2);
    node = v + 1 + octant;
  }
  const int v = probebake_octree[node];
  return v < 0 ? ~v : -1;
}

// Phase 3, a workgroup per seat, after every seat of the frame: the bake's stencils of the SVO leaves that
// name the cell's probes, where each of their probes is a leaf with a probe again (so that memory_svo keeps
// them, with the probes' current generations). Two seats naming one leaf write the same values.
void restore_stencils(uint s) {
  const CellSeat seat = seat_at(s);
  for (int e = int(gl_LocalInvocationIndex); e < seat.svo_leaves; e += int(MEMORY_WORKGROUP_SIZE)) {
    const int leaf = seat_data[seat.first_svo + e];
    const int at = probebake_info.svo_leaves + SEAT_STENCIL_VEC4S * leaf;
    const ivec4 xy = svo_bake[at], zd = svo_bake[at + 1];
    ivec4 probes = ivec4(-1);
    uvec4 generations = uvec4(0u);
    bool found = true;
    for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
      if (xy[k] < 0) continue;
      probes[k] = probe_at_key(xy[k], zd[k]);
      found = found && probes[k] >= 0;
      if (probes[k] >= 0) generations[k] = probe_generations[probes[k]];
    }
    if (!found) continue;
    probebake_svo_leaves[leaf].probes = probes;
    probebake_svo_leaves[leaf].weights = intBitsToFloat(svo_bake[at + 2]);
    svo_generations[leaf] = generations;
    probebake_svo_nodes[int(intBitsToFloat(svo_bake[leaf].w))] = ~leaf; // attached again if it was a miss
  }
}

void main() {
  if (push.phase == 1) { // one thread: the pops in arrival order
    if (gl_GlobalInvocationID.x != 0u) return;
    for (int i = 0; i < memory_frame.cell_changes; ++i) {
      const uint entry = memory_frame.cells[i];
      if ((entry & MEMORY_CELL_ARRIVED) != 0u) reserve(entry & ~MEMORY_CELL_ARRIVED);
    }
    return;
  }
  if (push.phase == 2) { // uniform per workgroup
    seat_subtree(probebake_flat_workgroup());
    return;
  }
  if (push.phase == 3) { // uniform per workgroup
    restore_stencils(probebake_flat_workgroup());
    return;
  }
  const int i = memory_item(memory_frame.cell_changes);
  if (i < 0) return;
  const uint entry = memory_frame.cells[i];
  if ((entry & MEMORY_CELL_ARRIVED) == 0u) drop(entry);
}
