// The adaptive octree's per-frame update on the CPU (octree thesis §3.2.1 memory update M0-M4, §3.2.2 the
// light update's state transitions L0-L3), on the thesis's buffers in a formats::ProbeVolume. It is the
// reference that the GPU passes are tested against; it decides the tree's shape and its probes'
// lifetimes, not their lighting (the light passes relight every probe it leaves in L1/L2).
//
// Where this departs from the thesis, and why:
// - Leaves are re-examined only where geometry changed: `changed` boxes are the union of a moving
//   object's old and new bounds, so the leaves an object leaves are re-measured too (the thesis tests
//   the objects' current boxes, and a leaf an object has left would keep its split forever).
// - M2 pushes the freed leaf back as L3 (the thesis drops it from the queue unless its parent frees the
//   cluster, after which no object could ever make it allocate again).
// - M1 pushes the parent with M0 like M3 does: both allocate under a parent that M4 might free.
// - M4 merges a parent whose children are all leaves when its own centre, measured now, would not split it
//   (the thesis waits until no child has a probe): merging mirrors splitting, so a pose settles to the same
//   tree whatever the path to it. A re-measured leaf that stays asks its parent to judge (M4).
// - M4 judges every parent on the tree as the frame found it and frees clusters after M1-M3, so the result
//   does not depend on the order of the entries and a freed cluster is not reused in the frame whose L0
//   entries retire its old children (the GPU: decide, allocate, then free, as three dispatches). An M1 that finds its pool
//   dry asks its parent to free the cluster again (its M0 may have hidden a sibling's M4).
// - L1 decides like the bake's placement: a centre that sees too little (f < split_low) or mostly back
//   faces (inside a solid) cannot judge its cube, so the cube splits when its centre sees any geometry
//   inside it (f > 0) and is below max depth, and its probe is freed otherwise (the thesis frees every
//   f < split_low, and a probe that lands inside an object would free the very cube the object fills).
// - New probes start from their parent's irradiance (M3) or from `initial_irradiance` (M1), not black.
// - Allocation takes from free lists (formats::Octree), never scans; a pool that runs dry leaves the
//   node as it was (M1 -> L3; M3 -> L1, measured and retried next frame) and is counted.
// - The per-frame limits apply to the costly work only (M1/M3 allocations, L1/L2 tracing and lighting);
//   a deferred leaf that a box touched waits as L1, so no change is missed.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/dynamic/leaf_queue.h"
#include "probebake/formats/octree.h"
#include "probebake/leaf_rule.h"

namespace probebake::dynamic {

struct Box {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
};

// What L1 learns by casting a probe's placement lattice in the scene's current pose (the bake's measure,
// placement/include/probebake/placement/probe_tracing.h): hits inside the node cube / rays, back-face hits / hits.
struct LeafTrace {
  float hit_fraction = 0.0f;
  float backface_fraction = 0.0f;
};

struct TreeUpdateSettings {
  int max_memory_entries = 0; // M1/M3 allocations per frame, 0 = all (M0, M2, M4 always run)
  int max_light_entries = 0;  // L1/L2 leaves traced or lit per frame, 0 = all (L0, L3 always run)
  float dead_backface_fraction = gpu::LEAF_DEAD_BACKFACE_FRACTION; // back-face fraction above which a centre is blind
};

struct TreeFrameStats {
  std::array<int, gpu::LEAF_STATE_COUNT> processed{}; // entries processed, by state
  int deferred = 0;                                   // entries left for a later frame by the per-frame limits
  int probes_placed = 0;                              // M1
  int probes_freed = 0;                               // M2
  int splits = 0;                                     // M3
  int collapses = 0;                                  // M4
  int failed_allocations = 0;                         // a pool ran dry: the node kept its state
  int lost_entries = 0;                               // a push into a full segment (0 while capacity >= octree nodes)
  int stale_entries = 0; // entries whose node no longer fits their state (0 unless the buffers were edited)
};

class TreeUpdate {
public:
  // Probe position, its node cube -> the lattice measure in the current pose.
  using TraceLeaf = std::function<LeafTrace(const formats::NodeCube& cube, glm::vec3 probe_position)>;
  // Fills the SH irradiance a probe placed at `position` starts from (the sampler's answer there).
  using InitialIrradiance = std::function<void(glm::vec3 position, float (&irradiance_sh)[gpu::PROBE_SH_FLOATS])>;

  // Seeds the leaf queue with every leaf (L2 with a probe, L3 without) when the volume has no queue yet.
  // The octree must use Growth::fixed to behave like the GPU's fixed pools.
  TreeUpdate(formats::Octree& tree, const TreeUpdateSettings& settings = {});

  // One frame: the memory update, then the light update's transitions.
  TreeFrameStats run_frame(std::span<const Box> changed, const TraceLeaf& trace, const InitialIrradiance& initial = {});

  void set_settings(const TreeUpdateSettings& settings) { settings_ = settings; }
  const LeafQueue& queue() const { return queue_; }

private:
  enum class Verdict { free, split, keep }; // what a measured leaf (or merging parent) becomes
  struct Frame;
  void memory_update(Frame& frame);
  void light_update(Frame& frame);
  void allocate_probe(Frame& frame, int node);
  void free_probe(Frame& frame, int node);
  void split(Frame& frame, int node);
  Verdict judge(const LeafTrace& trace, int depth) const;
  std::optional<Verdict> collapse_verdict(Frame& frame, int node) const;
  void collapse(Frame& frame, int node, Verdict becomes);
  void place_surfels(Frame& frame, int node);
  void push(Frame& frame, int segment, int node, int state);
  void push_parent(Frame& frame, int segment, int node, int state);
  bool fits_state(int node, int state) const;
  int batches_per_probe() const;

  formats::Octree* tree_;
  TreeUpdateSettings settings_;
  LeafQueue queue_;
};

// Every reachable leaf is in exactly one entry over the three segments, in a state that fits it (M1/L3
// without a probe, M2/M3/L1/L2 with one), and every other entry is a parent in M0 or M4. Returns the
// problems found, one line each (empty = consistent); the soak tests check it after every frame.
std::vector<std::string> check_queue_covers_tree(const formats::ProbeVolume& volume);

} // namespace probebake::dynamic
