// Shared steps of the memory update (memory_*.comp, octree thesis §3.2.1 with dynamic/tree_update.h's
// departures): leaf-queue segments as key -> state sets, the free-list stacks, probe and surfel-chain set-up
// and release. The including shader includes memory_bindings.glsl first.
#ifndef PROBEBAKE_MEMORY_UPDATE_GLSL
#define PROBEBAKE_MEMORY_UPDATE_GLSL

#include "probebake/dispatch.glsl"
#include "probebake/leaf_rule.h"
#include "probebake/octree.glsl"
#include "probebake/sample_irradiance.glsl"

int queue_capacity() { return leaf_header.segment_capacity; }
int queue_key_index(int segment, int node) { return segment * queue_capacity() + node; }
int queue_key(int state) { return (leaf_state_priority(state) << 4) | state; }

// This frame's segments (pull origin p already moved): memory pulls p, light p + 1 (LeafQueue's rule).
int memory_pull_segment() { return leaf_header.pull_origin; }
int light_pull_segment() { return (leaf_header.pull_origin + 1) % 3; }
int memory_light_out() { return (memory_pull_segment() + 1) % 3; }  // = light_pull_segment()
int memory_memory_out() { return (memory_pull_segment() + 2) % 3; }
int light_memory_out() { return (light_pull_segment() + 1) % 3; }   // = memory_memory_out()
int light_light_out() { return (light_pull_segment() + 2) % 3; }    // = memory_pull_segment()

// Adds (node, state) to `segment`, or raises the node's state there. The key is the set: the first push
// of a node appends its entry, later pushes only raise the key; memory_sync copies keys into entries.
void queue_push(int segment, int node, int state) {
  if (node < 0 || node >= queue_capacity()) { atomicAdd(memory_counters.lost_entries, 1); return; }
  const int old = atomicMax(queue_keys[queue_key_index(segment, node)], queue_key(state));
  if (old != 0) return;
  const int slot = atomicAdd(leaf_header.count[segment], 1);
  if (slot >= queue_capacity()) { atomicAdd(memory_counters.lost_entries, 1); return; } // memory_sync clamps the count
  leaf_entries[segment * queue_capacity() + slot] = LeafEntry(node, state);
}
void queue_push_parent(int segment, int node, int state) {
  if (node != 0) queue_push(segment, octree_parent_of(node), state);
}

// Streaming (memory_remeasure, memory_cells; after memory_collapse): queues live node `node` to be measured
// again, as a box touching it would: a leaf with a probe for L1, one without for M1 (its parent M0), a
// parent for M4.
void queue_measure_again(int node) {
  const int v = probebake_octree[node];
  if (v < 0) {
    queue_push(memory_light_out(), node, LEAF_L1_PLACE_SURFELS);
  } else if (v == 0) {
    queue_push(memory_memory_out(), node, LEAF_M1_ALLOCATE_PROBE);
    queue_push_parent(memory_memory_out(), node, LEAF_M0_CHILD_ALLOCATING);
  } else {
    queue_push(memory_memory_out(), node, LEAF_M4_FREE_CLUSTER);
  }
}

// Entry `index` of `segment` as pulled: its node and the state its key holds; the key and entry are cleared.
LeafEntry queue_take(int segment, int index) {
  const int at = segment * queue_capacity() + index;
  const int node = leaf_entries[at].node;
  leaf_entries[at] = LeafEntry(0, 0);
  if (node < 0 || node >= queue_capacity()) return LeafEntry(node, -1);
  const int key = queue_keys[queue_key_index(segment, node)];
  queue_keys[queue_key_index(segment, node)] = 0;
  return LeafEntry(node, key & MEMORY_KEY_STATE_MASK);
}

// Whether `node` can be in `state` (TreeUpdate::fits_state): the net under every transition.
bool node_fits_state(int node, int state) {
  if (state == LEAF_L0_PARENT_FREED) return true;
  if (!octree_is_live_node(node)) return false;
  const int v = probebake_octree[node];
  if (state == LEAF_M0_CHILD_ALLOCATING || state == LEAF_M4_FREE_CLUSTER) return v > 0;
  if (state == LEAF_M1_ALLOCATE_PROBE || state == LEAF_L3_CHECK_BOXES) return v == 0;
  return v < 0;
}

bool cube_touched(vec3 cube_min, float size) {
  for (int b = 0; b < min(memory_frame.box_count, MEMORY_MAX_BOXES); ++b) {
    const MemoryBox box = memory_frame.boxes[b];
    if (all(greaterThanEqual(box.upper, cube_min)) && all(lessThanEqual(box.lower, cube_min + vec3(size)))) return true;
  }
  return false;
}

// ---- Free lists: stacks whose top is in MemoryState; pushes append with an atomic, pops take ranges that
// memory_grant handed out (no dispatch both pushes and pops one stack).
void push_free_probe(int probe) { probe_stack_at(atomicAdd(memory_state.probe_top, 1)) = probe; }
void push_free_batch(int batch) { batch_stack_at(atomicAdd(memory_state.batch_top, 1)) = batch; }
void push_free_cluster(int meta) { cluster_stack_at(atomicAdd(memory_state.cluster_top, 1)) = meta; }

void clear_sh(int probe) {
  for (int k = 0; k < PROBE_SH_FLOATS; ++k) probebake_probes[probe].irradiance_sh[k] = 0.0;
}

// Frees the probe and its surfel chain onto the free lists and zeroes the probe (formats::Octree::free_probe);
// the caller clears the octree node. Only in dispatches that pop nothing (memory_release). The slot's generation moves on, so the SVO drops it.
void release_probe(int probe) {
  int link = probebake_probes[probe].link;
  if (~link != PROBE_NO_SURFELS) {
    int batch = ~link;
    for (int steps = 0; steps <= probebake_info.batch_capacity && batch >= 0 && batch < probebake_info.batch_capacity; ++steps) {
      const int next = surfel_batches[batch].link;
      surfel_batches[batch].link = 0;
      surfel_batches[batch].probe = 0;
      surfel_batches[batch].count = 0;
      surfel_batches[batch].first = 0;
      push_free_batch(batch);
      if (next >= 0) break;
      batch = ~next;
    }
  }
  probebake_probes[probe].position = vec3(0.0);
  probebake_probes[probe].link = 0;
  probebake_probes[probe].node = 0;
  probebake_probes[probe].depth = 0;
  probebake_probes[probe].hit_fraction = 0.0;
  probebake_probes[probe].backface_fraction = 0.0;
  probebake_probes[probe].pad0 = 0.0;
  clear_sh(probe);
  trace_flags[probe] = 0u;
  atomicAdd(probe_generations[probe], 1u);
  push_free_probe(probe);
}

// Makes `probe` the probe of leaf `node` (its cube given): position at the centre, node, depth; keeps link
// and irradiance (the caller sets them) and asks the light update for its records.
void seat_probe(int probe, int node, vec3 cube_min, float size, int depth) {
  probebake_probes[probe].position = cube_min + vec3(0.5 * size);
  probebake_probes[probe].node = node;
  probebake_probes[probe].depth = depth;
  probebake_probes[probe].hit_fraction = 0.0;
  probebake_probes[probe].backface_fraction = 0.0;
  probebake_probes[probe].pad0 = 0.0;
  probebake_octree[node] = ~probe;
  trace_flags[probe] = TRACE_FLAG_RETRACE;
}

// Gives a probe that has none the surfel chain of batches batch_stack[first, first + batches_per_probe)
// (TreeUpdate::place_surfels: lattice points in chained batches; L1 fills them).
void give_surfel_chain(int probe, int first) {
  const int count = memory_frame.batches_per_probe;
  if (count <= 0) { probebake_probes[probe].link = ~PROBE_NO_SURFELS; return; }
  const int total = probebake_info.surfels_per_probe;
  for (int b = 0; b < count; ++b) {
    const int batch = batch_stack_at(first + b);
    surfel_batches[batch].link = b + 1 < count ? ~batch_stack_at(first + b + 1) : probe + 1;
    surfel_batches[batch].probe = probe;
    surfel_batches[batch].first = b * SURFELS_PER_BATCH;
    surfel_batches[batch].count = min(SURFELS_PER_BATCH, total - b * SURFELS_PER_BATCH);
  }
  probebake_probes[probe].link = ~batch_stack_at(first);
}

// Zeroes the surfels of a chain that changes owner node (a split's first child, a merge keeping a child's probe).
void clear_surfel_chain(int probe) {
  int link = probebake_probes[probe].link;
  if (~link == PROBE_NO_SURFELS) return;
  int batch = ~link;
  for (int steps = 0; steps <= probebake_info.batch_capacity && batch >= 0 && batch < probebake_info.batch_capacity; ++steps) {
    for (int s = 0; s < SURFELS_PER_BATCH; ++s)
      surfel_batches[batch].surfels[s] = Surfel(vec3(0.0), 0.0, vec3(0.0), 0u, vec3(0.0), 0.0, vec3(0.0), 0.0);
    const int next = surfel_batches[batch].link;
    if (next >= 0) break;
    batch = ~next;
  }
}

// Whether slot k of SVO leaf `leaf` still names the probe it was filled with (not freed, not reused since).
bool svo_slot_live(int leaf, int k) {
  const int p = probebake_svo_leaves[leaf].probes[k];
  if (p < 0 || p >= probebake_info.probe_capacity || probebake_probes[p].link == 0) return false;
  return probe_generations[p] == svo_generations[leaf][k];
}

// The irradiance a probe without a parent probe starts from: the SVO stencil's probes at `position`,
// weighted as stored (the sampler's lookup without a normal), live probes only.
void initial_irradiance(int probe, vec3 position) {
  clear_sh(probe);
  const int leaf = probebake_find_svo_leaf(position);
  if (leaf < 0) return;
  float sum = 0.0;
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
    const int p = probebake_svo_leaves[leaf].probes[k];
    if (!svo_slot_live(leaf, k) || p == probe) continue;
    const float w = probebake_svo_leaves[leaf].weights[k];
    for (int c = 0; c < PROBE_SH_FLOATS; ++c) probebake_probes[probe].irradiance_sh[c] += w * probebake_probes[p].irradiance_sh[c];
    sum += w;
  }
  if (!(sum > 0.0)) { clear_sh(probe); return; }
  for (int c = 0; c < PROBE_SH_FLOATS; ++c) probebake_probes[probe].irradiance_sh[c] /= sum;
}

// One thread per work item over `count` items; returns the item or -1.
int memory_item(int count) {
  const uint i = probebake_flat_workgroup() * MEMORY_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  return i < uint(count) ? int(i) : -1;
}

#endif // PROBEBAKE_MEMORY_UPDATE_GLSL
