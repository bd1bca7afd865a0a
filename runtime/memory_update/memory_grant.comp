// Memory update, grant (one thread): walks the pulled entries in queue order and hands out pool elements as
// TreeUpdate does: the per-frame limit on M1/M3 (over it: deferred), then each allocation only when its pool
// holds enough (M1: a probe and its batches; M3: a cluster and eight probes with batches, of which the
// parent's probe becomes the first child's, so seven are taken), then merges that need a fresh probe. Only
// this thread moves the stacks' tops down; memory_allocate and memory_collapse take the granted ranges.
// The counts of the frame (processed, deferred, stale, failed) are kept here, in entry order.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = 1) in;

int clusters, probes, batches; // free elements not yet granted

bool take(int c, int p, int b, inout MemoryWork w) {
  w.cluster_first = clusters - c;
  w.probe_first = probes - p;
  w.batch_first = batches - b;
  clusters -= c;
  probes -= p;
  batches -= b;
  return true;
}

void grant_allocation(inout MemoryWork w, inout int allocations) {
  const int budget = memory_frame.max_memory_entries > 0 ? memory_frame.max_memory_entries : 0x7fffffff;
  if (allocations++ >= budget) {
    w.action = MEMORY_ACTION_DEFER;
    memory_counters.deferred += 1;
    return;
  }
  memory_counters.processed[w.state] += 1;
  const int bpp = memory_frame.batches_per_probe;
  if (w.action == MEMORY_ACTION_ALLOCATE_PROBE) {
    if (probes >= 1 && batches >= bpp) take(0, 1, bpp, w);
    else { w.action = MEMORY_ACTION_DRY; memory_counters.failed_allocations += 1; }
    return;
  }
  // M3: TreeUpdate's room test counts all eight probes, before the parent's is given back.
  const bool room = clusters >= 1 && probes >= 8 && batches >= 8 * bpp;
  if (probebake_probes[~probebake_octree[w.node]].depth >= probebake_info.max_depth || !room) {
    if (room) memory_counters.stale_entries += 1; // M3 at max depth: a lowered max depth
    else memory_counters.failed_allocations += 1;
    w.action = room ? MEMORY_ACTION_SPLIT_AT_MAX : MEMORY_ACTION_DRY;
    return;
  }
  take(1, 7, 7 * bpp, w);
}

void main() {
  clusters = memory_state.cluster_top;
  probes = memory_state.probe_top;
  batches = memory_state.batch_top;
  int allocations = 0;
  const int pulled = memory_state.memory_pulled;
  for (int i = 0; i < pulled; ++i) {
    MemoryWork w = memory_work[i];
    if (w.action == MEMORY_ACTION_STALE) memory_counters.stale_entries += 1;
    else if (w.action == MEMORY_ACTION_ALLOCATE_PROBE || w.action == MEMORY_ACTION_SPLIT) grant_allocation(w, allocations);
    else memory_counters.processed[w.state] += 1;
    memory_work[i] = w;
  }
  // Merges that stay lit without a child's probe to keep (TreeUpdate gives them one from the pool).
  const int bpp = memory_frame.batches_per_probe;
  for (int i = 0; i < pulled; ++i) {
    MemoryWork w = memory_work[i];
    if (w.action != MEMORY_ACTION_COLLAPSE || w.verdict != LEAF_VERDICT_KEEP || w.reuse_probe >= 0) continue;
    if (probes >= 1 && batches >= bpp) take(0, 1, bpp, w);
    else { w.verdict = LEAF_VERDICT_FREE; memory_counters.failed_allocations += 1; }
    memory_work[i] = w;
  }
  memory_state.cluster_top = clusters;
  memory_state.probe_top = probes;
  memory_state.batch_top = batches;
}
