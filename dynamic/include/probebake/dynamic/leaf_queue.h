// The leaf buffer of the octree thesis (§3.1.4, figure 3.3): three segments of (node, state) entries used
// as a ring, stored in the volume's leaf_queue_header / leaf_entries (the same bytes the GPU uses).
//
// Each frame the pull origin moves, p <- (p + 2) mod 3. The memory update (pull offset 0) pulls segment p,
// the light update (pull offset 1) pulls p + 1; a pass pushes states of the other kind into its pull
// segment + 1 and states of its own kind into its pull segment + 2. So segment p + 1 collects the light
// states for this frame's light update, p + 2 the memory states for the next frame, and segment p, once
// pulled, the light states for the next frame.
//
// Each segment is a set keyed by node: a node pushed twice into one segment is one entry whose state is
// the one of higher priority (state_priority), so no leaf is processed twice in a frame. The GPU keeps the
// same set with a per-node stamp; here an index map (side data, rebuilt from the entries).
#pragma once

#include <unordered_map>
#include <vector>

#include "probebake/formats/probe_volume.h"

namespace probebake::dynamic {

inline constexpr int kMemoryPullOffset = 0;
inline constexpr int kLightPullOffset = 1;

bool is_memory_state(int state); // LEAF_M0 .. LEAF_M4
// Which of two states for the same node in one segment wins: M0 (a child is allocating) over M4 (free the
// children) over the leaf's own M3 > M2 > M1; L0 (parent freed) over L1 (re-place surfels) > L2 > L3.
int state_priority(int state);

class LeafQueue {
public:
  // Uses the volume's leaf buffer; gives it one with `segment_capacity` entries per segment when it has
  // none. Throws Error(input) when the stored buffer is malformed (counts, duplicates, states).
  LeafQueue(formats::ProbeVolume& volume, int segment_capacity);

  // p <- (p + 2) mod 3; call once at the start of a frame.
  void begin_frame();
  // Segment pulled by the pass with this pull offset this frame, and its push targets.
  int pull_segment(int pull_offset) const;
  int other_kind_segment(int pull_offset) const { return (pull_segment(pull_offset) + 1) % 3; }
  int same_kind_segment(int pull_offset) const { return (pull_segment(pull_offset) + 2) % 3; }

  // Removes and returns every entry of `segment`, in push order.
  std::vector<gpu::LeafEntry> take(int segment);
  // Adds (node, state) to `segment`, or raises the state of the node's entry there. Returns false when
  // the segment is full (the entry is lost: the caller counts it; capacity >= octree nodes prevents it).
  bool push(int segment, int node, int state);

  int count(int segment) const;
  int capacity() const;
  std::vector<gpu::LeafEntry> entries(int segment) const;

private:
  formats::ProbeVolume* volume_;
  std::unordered_map<int, int> slot_[3]; // node -> entry index within the segment
};

} // namespace probebake::dynamic
