// Structs and constants of the runtime's memory update (octree thesis §3.2.1, M0-M4) and of the light
// update's state transitions (§3.2.2, L0-L3) on the GPU, shared by C++ and GLSL like gpu_types.h: std430,
// explicit padding, static_assert on sizes and offsets (C++ side). docs/RUNTIME_INTERNALS.md describes the
// buffers.
#ifndef PROBEBAKE_MEMORY_TYPES_H
#define PROBEBAKE_MEMORY_TYPES_H

#include "probebake/gpu_types.h"

PB_GPU_BEGIN

// Threads per workgroup of the per-entry dispatches (one leaf-queue entry or one SVO leaf per thread).
PB_CONSTANT(uint, MEMORY_WORKGROUP_SIZE, 64u);
// Changed boxes per frame (FrameInputs::changed_boxes beyond this are merged by the host into their union).
PB_CONSTANT(int, MEMORY_MAX_BOXES, 64);
// Streaming cells that drop or arrive per frame (MemoryFrame::cells; more wait for the next frame on the
// host). An entry is the cell's index in its grid (cells.h: x + n * (y + n * z)), with MEMORY_CELL_ARRIVED
// set for an arrival.
PB_CONSTANT(int, MEMORY_MAX_CELL_CHANGES, 1024);
PB_CONSTANT(uint, MEMORY_CELL_ARRIVED, 0x80000000u); // the rest of an arrival's entry: its CellSeat
// Ints of seat data behind MemoryFrame in the frame buffer with streaming (CellSeat records, their words,
// probes and stencils), the most StreamingOptions::max_seat_bytes allows; arrivals that do not fit wait for
// the next frame on the host, and a cell whose seat alone exceeds the limit (about 1,300 probes at this one)
// grows by measures instead (CellSeat::clusters -1).
PB_CONSTANT(int, MEMORY_SEAT_INTS, 49152);
// With streaming, the bake's stencil of SVO leaf l follows the leaf centres in MEMORY_BINDING_SVO_BAKE, as
// 16-byte entries [svo_leaves + 3 l, + 3): per stencil probe its leaf's key, x | y << 16 (integer
// coordinates at its depth; -1: no probe), then z | depth << 16, then the 4 weights (float bits). The
// shaders read the buffer as ints, so that no key is read as a (denormal, flushable) float. A seat names the leaves whose
// stencils name its cell's probes; the stencil comes back where each key is a leaf with a probe again.
PB_CONSTANT(int, SEAT_STENCIL_VEC4S, 3);

// A queue key: (state_priority << 4) | state, 0 = the node is not in the segment (leaf_rule.h's priority).
PB_CONSTANT(int, MEMORY_KEY_STATE_MASK, 15);

// What the memory update does with a pulled entry (MemoryWork::action).
PB_CONSTANT(int, MEMORY_ACTION_NONE, 0);           // M0, or a stale entry: nothing
PB_CONSTANT(int, MEMORY_ACTION_ALLOCATE_PROBE, 1); // M1
PB_CONSTANT(int, MEMORY_ACTION_FREE_PROBE, 2);     // M2
PB_CONSTANT(int, MEMORY_ACTION_SPLIT, 3);          // M3
PB_CONSTANT(int, MEMORY_ACTION_COLLAPSE, 4);       // M4 whose verdict merges the children
PB_CONSTANT(int, MEMORY_ACTION_DEFER, 5);          // M1/M3 over the per-frame limit: pushed back unchanged
PB_CONSTANT(int, MEMORY_ACTION_DRY, 6);            // M1/M3 whose pool ran dry: the node keeps its state
PB_CONSTANT(int, MEMORY_ACTION_SPLIT_AT_MAX, 7);   // M3 at max depth (a lowered max depth): measured again
PB_CONSTANT(int, MEMORY_ACTION_STALE, 8);          // the node no longer fits the entry's state
PB_CONSTANT(int, MEMORY_ACTION_SEAT, 9);           // streaming: memory_cells seats a cell (work indexed by seat)

// Per-node marks of the frame (MemoryState-sized int per octree element), cleared by memory_collapse.
PB_CONSTANT(int, MEMORY_MARK_FREEING,
            -1); // an M2 leaf freeing its probe this frame; > 0: 1 + LEAF_VERDICT_* of a merging parent
// Streaming: a leaf (L1) or parent (M4) whose measure crossed a cell that is out, kept as it was until cells
// arrive (memory_remeasure), across frames; decide overwrites it and collapse clears it like the others.
PB_CONSTANT(int, MEMORY_MARK_REMEASURE, -2);

struct MemoryPush {
  int phase; // offset 0: memory_begin: 0 = memory update, 1 = light transitions
  int pad0;  // offset 4
  int pad1;  // offset 8
  int pad2;  // offset 12
};           // size 16

// Host-written inputs of one frame (vkCmdUpdateBuffer before the memory update).
struct MemoryBox {
  vec3 lower; // offset  0: minimum corner, world space
  float pad0; // offset 12
  vec3 upper; // offset 16: maximum corner
  float pad1; // offset 28
};            // size 32

struct MemoryFrame {
  int box_count;                       // offset  0: changed boxes in use
  int max_memory_entries;              // offset  4: M1/M3 per frame, 0 = all
  int max_light_entries;               // offset  8: L1/L2 leaves with a probe per frame, 0 = all
  float dead_backface_fraction;        // offset 12: leaf_rule.h
  int batches_per_probe;               // offset 16: surfel batches of a new probe (0 without a batch pool)
  uint null_leaf;                      // offset 20: streaming: the child word of a cell that is out, else 0; a
                                       //   measure whose lattice ray crosses one decides nothing (octree.glsl)
  int cell_changes;                    // offset 24: entries of cells in use (memory_cells)
  int cell_depth;                      // offset 28: the octree depth of the cells (VolumeInfo's octree), 0 = none
  MemoryBox boxes[MEMORY_MAX_BOXES];   // offset 32
  uint cells[MEMORY_MAX_CELL_CHANGES]; // offset 32 + 32 * MEMORY_MAX_BOXES: cells dropped or arrived
};                                     // size 32 + 32 * MEMORY_MAX_BOXES + 4 * MEMORY_MAX_CELL_CHANGES

// Streaming: an arriving cell's subtree as the file has it, in the seat data behind MemoryFrame (ints;
// memory_cells seats it from the pools). A word is a node's: > 0 an inner node whose cluster is local
// cluster word - 1, < 0 a leaf with local probe ~word, 0 a leaf without a probe.
// The seat data's layout, written by the host (MemoryUpdatePass::take_cell_changes) and read by
// memory_cells.comp: one CellSeat record of SEAT_HEADER_INTS ints per arrival of the frame, then each
// arrival's body: its cluster words (OCTREE_CLUSTER_SIZE per cluster), its probes (a Probe's bytes,
// SEAT_PROBE_INTS ints each) and its SVO leaves.
PB_CONSTANT(int, SEAT_HEADER_INTS, 8); // ints of one CellSeat record: sizeof(CellSeat) / 4
PB_CONSTANT(int, SEAT_PROBE_INTS, 36); // ints of one probe: sizeof(Probe) / 4
struct CellSeat {
  uint cell;       // offset  0: grid index (cells.h)
  int clusters;    // offset  4: clusters below the cell's node; -1: too large for the seat data (it grows
                   //   by measures instead)
  int probes;      // offset  8: probes of the subtree
  int node_word;   // offset 12: the cell's node's word
  int first_word;  // offset 16: seat-data index of 9 ints per cluster: the parent's slot (8 c + octant of
                   //   local cluster c, -1 = the cell's node), then its 8 nodes' words
  int first_probe; // offset 20: seat-data index of the probes (Probe, SEAT_PROBE_INTS ints each), local probe order
  int svo_leaves;  // offset 24: SVO leaves whose bake stencils name a probe of the cell (in any cell)
  int first_svo;   // offset 28: seat-data index of their indices (SEAT_STENCIL_VEC4S)
};                 // size 32

// Device-only state: free-list stack sizes, the frame's pulled counts, and the indirect dispatch sizes that
// memory_begin derives from them (VkDispatchIndirectCommand, folded into y past LIGHT_LIST_MAX_GROUPS_X).
struct MemoryState {
  int cluster_top;             // offset  0: free node clusters (meta indices) on the cluster stack
  int probe_top;               // offset  4: free probe slots on the probe stack
  int batch_top;               // offset  8: free surfel batches on the batch stack
  int traced;                  // offset 12: L1/L2 leaves with a probe taken so far this frame (light limit)
  int memory_pulled;           // offset 16: entries the memory update pulled this frame
  int memory_segment;          // offset 20: the segment it pulled
  int light_pulled;            // offset 24: entries the light update pulled this frame
  int light_segment;           // offset 28: the segment it pulled
  uint entry_groups[3];        // offset 32: one workgroup per pulled memory entry (memory_decide)
  uint entry_thread_groups[3]; // offset 44: one thread per pulled memory entry (release, allocate, collapse)
  uint light_groups[3];        // offset 56: one workgroup per pulled light entry (memory_light)
  int probe_stack_base;        // offset 68: the probe stack's first element in the free-stack buffer
  int batch_stack_base;        // offset 72: the batch stack's (the cluster stack starts at 0)
  int pad0;                    // offset 76
};                             // size 80 (the queue keys follow it in the state buffer)

// One pulled memory entry as the dispatches pass it on: decide fills node/state/action, release the
// merge probe, grant the stack positions (index into the stacks of the first element granted).
struct MemoryWork {
  int node;          // offset  0
  int state;         // offset  4: LEAF_M*
  int action;        // offset  8: MEMORY_ACTION_*
  int verdict;       // offset 12: LEAF_VERDICT_* of a merge (MEMORY_ACTION_COLLAPSE)
  int reuse_probe;   // offset 16: a merging child's probe kept for the merged node, -1 = none
  int cluster_first; // offset 20: granted: cluster stack position
  int probe_first;   // offset 24: granted: probe stack position
  int batch_first;   // offset 28: granted: batch stack position
  int merged;        // offset 32: children whose probes the merge averaged (MEMORY_ACTION_COLLAPSE)
  int pad0;          // offset 36
  int pad1;          // offset 40
  int pad2;          // offset 44
};                   // size 48

// Statistics of one frame's memory update and light transitions, reset every frame.
struct MemoryCounters {
  int processed[LEAF_STATE_COUNT]; // offset  0: entries processed, by state
  int deferred;                    // offset 36: entries left for a later frame by the per-frame limits
  int probes_placed;               // offset 40: M1 and merged parents
  int probes_freed;                // offset 44: M2 and merged children
  int splits;                      // offset 48: M3
  int collapses;                   // offset 52: M4 merges
  int failed_allocations;          // offset 56: a pool ran dry: the node kept its state
  int lost_entries;                // offset 60: pushes into a full segment (0 while capacity >= nodes)
  int stale_entries;               // offset 64: entries whose node no longer fits their state
  int svo_slots_dropped;           // offset 68: SVO stencil slots whose probe was freed or reused
  int svo_leaves_refilled;         // offset 72: SVO leaves left empty and refilled from the octree
  int free_clusters;               // offset 76: pool use at the end of the frame (memory_sync)
  int free_probes;                 // offset 80
  int free_batches;                // offset 84
  int unresolved_measures;         // offset 88: streaming: L1/M4 measures that crossed a cell that is out
  int cells_collapsed;             // offset 92: streaming: dropped cells whose subtree went back to the pools
};                                 // size 96

#ifdef __cplusplus
static_assert(sizeof(MemoryPush) == 16);
static_assert(SVO_PROBES_PER_LEAF == 4 && OCTREE_MAX_DEPTH < 16); // a key per vec4 lane, 16-bit coordinates
static_assert(sizeof(CellSeat) == 32 && sizeof(MemoryFrame) % 16 == 0);
static_assert(sizeof(CellSeat) == SEAT_HEADER_INTS * 4 && sizeof(Probe) == SEAT_PROBE_INTS * 4);
static_assert(sizeof(MemoryBox) == 32 && offsetof(MemoryBox, upper) == 16);
static_assert(sizeof(MemoryFrame) == 32 + 32 * MEMORY_MAX_BOXES + 4 * MEMORY_MAX_CELL_CHANGES &&
              offsetof(MemoryFrame, boxes) == 32);
static_assert(offsetof(MemoryFrame, cells) == 32 + 32 * MEMORY_MAX_BOXES && offsetof(MemoryFrame, cell_depth) == 28);
static_assert(offsetof(MemoryFrame, batches_per_probe) == 16 && offsetof(MemoryFrame, null_leaf) == 20);
static_assert(sizeof(MemoryState) == 80 && offsetof(MemoryState, light_segment) == 28);
static_assert(offsetof(MemoryState, entry_groups) == 32 && offsetof(MemoryState, entry_thread_groups) == 44 &&
              offsetof(MemoryState, light_groups) == 56 && offsetof(MemoryState, probe_stack_base) == 68 &&
              offsetof(MemoryState, batch_stack_base) == 72);
static_assert(sizeof(MemoryWork) == 48 && offsetof(MemoryWork, merged) == 32);
static_assert(sizeof(MemoryCounters) == 96 && offsetof(MemoryCounters, deferred) == 36);
static_assert(offsetof(MemoryCounters, stale_entries) == 64 && offsetof(MemoryCounters, svo_leaves_refilled) == 72);
static_assert(offsetof(MemoryCounters, free_clusters) == 76 && offsetof(MemoryCounters, free_batches) == 84);
static_assert(offsetof(MemoryCounters, unresolved_measures) == 88 && offsetof(MemoryCounters, cells_collapsed) == 92);
#endif
PB_GPU_END

#endif // PROBEBAKE_MEMORY_TYPES_H
