#include "probebake/dynamic/tree_update.h"

#include <algorithm>
#include <optional>
#include <string>
#include <unordered_map>

#include "probebake/formats/error.h"
#include "probebake/leaf_rule.h"

namespace probebake::dynamic {

using formats::kNoIndex;

struct TreeUpdate::Frame {
  std::span<const Box> changed;
  const TraceLeaf* trace = nullptr;
  const InitialIrradiance* initial = nullptr;
  TreeFrameStats stats;
  std::unordered_map<int, Verdict> collapsing; // parents freed this frame -> what they become
};

namespace {

bool overlaps(const formats::NodeCube& cube, const Box& box) {
  for (int a = 0; a < 3; ++a) {
    if (box.max[a] < cube.min[a] || box.min[a] > cube.min[a] + cube.size) return false;
  }
  return true;
}

bool touched(const formats::NodeCube& cube, std::span<const Box> changed) {
  return std::any_of(changed.begin(), changed.end(), [&](const Box& b) { return overlaps(cube, b); });
}

// The root, or a node of an allocated cluster.
bool is_live_node(const formats::ProbeVolume& v, int node) {
  if (node == 0) return !v.octree.empty();
  if (node < 0 || std::size_t(node) >= v.octree.size() || !formats::is_node_index(node)) return false;
  return v.octree[std::size_t(formats::cluster_meta_of(node))] < 0;
}

int parent_of(const formats::ProbeVolume& v, int node) {
  return node == 0 ? kNoIndex : ~v.octree[std::size_t(formats::cluster_meta_of(node))];
}

int limit_or_all(int limit, std::size_t count) { return limit > 0 ? std::min(limit, int(count)) : int(count); }

} // namespace

TreeUpdate::TreeUpdate(formats::Octree& tree, const TreeUpdateSettings& settings)
    : tree_(&tree),
      settings_(settings),
      queue_(tree.volume(), int(std::max<std::size_t>(tree.volume().octree.size(), 1))) {
  formats::ProbeVolume& v = tree.volume();
  if (queue_.count(0) + queue_.count(1) + queue_.count(2) > 0) return;
  // Seed the segment the first frame's light update pulls (begin_frame moves the origin first).
  const int seed = (v.leaf_header.pull_origin + 2 + kLightPullOffset) % 3;
  formats::for_each_leaf(v, [&](const formats::NodeCube& leaf) {
    queue_.push(seed, leaf.node, tree.probe_of(leaf.node) == kNoIndex ? gpu::LEAF_L3_CHECK_BOXES : gpu::LEAF_L2_LIGHT);
  });
}

TreeFrameStats TreeUpdate::run_frame(std::span<const Box> changed, const TraceLeaf& trace,
                                     const InitialIrradiance& initial) {
  Frame frame{changed, &trace, &initial, {}, {}};
  queue_.begin_frame();
  memory_update(frame);
  light_update(frame);
  return frame.stats;
}

void TreeUpdate::push(Frame& frame, int segment, int node, int state) {
  if (!queue_.push(segment, node, state)) ++frame.stats.lost_entries;
}

void TreeUpdate::push_parent(Frame& frame, int segment, int node, int state) {
  if (node != 0) push(frame, segment, parent_of(tree_->volume(), node), state);
}

// Whether `node` can be in `state`: the net under every transition, so that an edited or stale buffer
// never makes the update act on a node that is not what its entry says.
bool TreeUpdate::fits_state(int node, int state) const {
  const formats::ProbeVolume& v = tree_->volume();
  if (state == gpu::LEAF_L0_PARENT_FREED) return true; // dropped unread
  if (!is_live_node(v, node)) return false;
  switch (state) {
  case gpu::LEAF_M0_CHILD_ALLOCATING:
  case gpu::LEAF_M4_FREE_CLUSTER: return !tree_->is_leaf(node);
  case gpu::LEAF_M1_ALLOCATE_PROBE:
  case gpu::LEAF_L3_CHECK_BOXES: return tree_->is_leaf(node) && tree_->probe_of(node) == kNoIndex;
  default: return tree_->is_leaf(node) && tree_->probe_of(node) != kNoIndex;
  }
}

int TreeUpdate::batches_per_probe() const {
  const formats::ProbeVolume& v = tree_->volume();
  if (v.surfel_batches.empty()) return 0;
  return (v.info.surfels_per_probe + gpu::SURFELS_PER_BATCH - 1) / gpu::SURFELS_PER_BATCH;
}

// ---- Memory update (thesis §3.2.1) -------------------------------------------------------------------------

void TreeUpdate::memory_update(Frame& frame) {
  const int pull = queue_.pull_segment(kMemoryPullOffset);
  const int memory_out = queue_.same_kind_segment(kMemoryPullOffset);
  const std::vector<gpu::LeafEntry> entries = queue_.take(pull);
  const int budget = limit_or_all(settings_.max_memory_entries, entries.size()); // M1 and M3 only

  std::vector<gpu::LeafEntry> leaf_work;
  std::vector<int> free_cluster_requests;
  int allocations = 0;
  for (const gpu::LeafEntry& e : entries) {
    if (!fits_state(e.node, e.state)) {
      ++frame.stats.stale_entries;
      continue;
    }
    const bool allocates = e.state == gpu::LEAF_M1_ALLOCATE_PROBE || e.state == gpu::LEAF_M3_SPLIT;
    if (allocates && allocations++ >= budget) {
      // Deferred: it keeps its state, and holds its parent in M0 meanwhile. Both end in a fresh L1
      // measurement, so the boxes it misses while it waits are not lost.
      push(frame, memory_out, e.node, e.state);
      push_parent(frame, memory_out, e.node, gpu::LEAF_M0_CHILD_ALLOCATING);
      ++frame.stats.deferred;
      continue;
    }
    ++frame.stats.processed[std::size_t(e.state)];
    if (e.state == gpu::LEAF_M4_FREE_CLUSTER)
      free_cluster_requests.push_back(e.node);
    else if (e.state != gpu::LEAF_M0_CHILD_ALLOCATING)
      leaf_work.push_back(e); // M0: leave the cluster alone
  }

  // M4 is judged on the tree as the frame found it and applied after M1-M3: no collapse meets a child that
  // changes in the same frame (an allocating child holds its parent in M0), and a freed cluster returns
  // to the pool only after this frame's splits, so no new child can share a node index with the L0
  // entries that retire the old children.
  for (const int node : free_cluster_requests) {
    if (const std::optional<Verdict> becomes = collapse_verdict(frame, node)) frame.collapsing.emplace(node, *becomes);
  }
  for (const gpu::LeafEntry& e : leaf_work) {
    if (e.state == gpu::LEAF_M1_ALLOCATE_PROBE)
      allocate_probe(frame, e.node);
    else if (e.state == gpu::LEAF_M2_FREE_PROBE)
      free_probe(frame, e.node);
    else
      split(frame, e.node);
  }
  for (const int node : free_cluster_requests) {
    if (const auto found = frame.collapsing.find(node); found != frame.collapsing.end())
      collapse(frame, node, found->second);
  }
}

void TreeUpdate::allocate_probe(Frame& frame, int node) {
  const int light_out = queue_.other_kind_segment(kMemoryPullOffset);
  if (tree_->free_probes() < 1 || tree_->free_batches() < batches_per_probe()) {
    ++frame.stats.failed_allocations;
    push(frame, light_out, node, gpu::LEAF_L3_CHECK_BOXES);
    // Its M0 may have hidden a sibling's request to free the cluster: ask again.
    push_parent(frame, queue_.same_kind_segment(kMemoryPullOffset), node, gpu::LEAF_M4_FREE_CLUSTER);
    return;
  }
  const int probe = tree_->place_probe(node);
  gpu::Probe& p = tree_->volume().probes[std::size_t(probe)];
  if (*frame.initial) (*frame.initial)(p.position, p.irradiance_sh);
  place_surfels(frame, node);
  ++frame.stats.probes_placed;
  push(frame, light_out, node, gpu::LEAF_L1_PLACE_SURFELS);
}

void TreeUpdate::free_probe(Frame& frame, int node) {
  tree_->free_probe(tree_->probe_of(node));
  ++frame.stats.probes_freed;
  push(frame, queue_.other_kind_segment(kMemoryPullOffset), node, gpu::LEAF_L3_CHECK_BOXES);
  // Its parent may free the cluster now, unless it does so this very frame (the leaf is about to be gone).
  if (node != 0 && !frame.collapsing.contains(parent_of(tree_->volume(), node))) {
    push_parent(frame, queue_.same_kind_segment(kMemoryPullOffset), node, gpu::LEAF_M4_FREE_CLUSTER);
  }
}

void TreeUpdate::split(Frame& frame, int node) {
  const int light_out = queue_.other_kind_segment(kMemoryPullOffset);
  formats::ProbeVolume& v = tree_->volume();
  const gpu::Probe& parent = v.probes[std::size_t(tree_->probe_of(node))];
  const int depth = parent.depth;
  // The eight children's probes and batches must exist before the parent's are given back (as on the
  // GPU, where they are taken from the pools first).
  const bool room =
      tree_->free_clusters() >= 1 && tree_->free_probes() >= 8 && tree_->free_batches() >= 8 * batches_per_probe();
  if (depth >= v.info.max_depth || !room) {
    if (room)
      ++frame.stats.stale_entries; // M3 at max depth: L1 never asks for it
    else
      ++frame.stats.failed_allocations;
    // L1, not the thesis's L2: it measures again next frame (retrying the split while the pool is dry,
    // and seeing any change that the wait hid).
    push(frame, light_out, node, gpu::LEAF_L1_PLACE_SURFELS);
    return;
  }
  float parent_sh[gpu::PROBE_SH_FLOATS];
  std::copy(std::begin(parent.irradiance_sh), std::end(parent.irradiance_sh), parent_sh); // split() frees the probe
  const int meta = tree_->split(node); // frees the parent's probe and surfels
  for (int octant = 0; octant < 8; ++octant) {
    const int child = formats::child_node(meta, octant);
    const int probe = tree_->place_probe(child);
    std::copy(std::begin(parent_sh), std::end(parent_sh), v.probes[std::size_t(probe)].irradiance_sh);
    place_surfels(frame, child);
    push(frame, light_out, child, gpu::LEAF_L1_PLACE_SURFELS);
  }
  ++frame.stats.splits;
}

// M4: a parent whose children are all leaves merges them when its own centre, measured now, would not split
// it (the rule L1 applies to a leaf). This makes merging the mirror of splitting, so the tree a pose
// settles to does not depend on the path to it (the thesis merges only when no child has a probe, and a
// split that a passing object caused stays wherever a child still sees static geometry).
std::optional<TreeUpdate::Verdict> TreeUpdate::collapse_verdict(Frame& frame, int node) const {
  const formats::ProbeVolume& v = tree_->volume();
  const int meta = v.octree[std::size_t(node)];
  for (int octant = 0; octant < 8; ++octant) {
    if (!tree_->is_leaf(formats::child_node(meta, octant))) return std::nullopt;
  }
  const formats::NodeCube cube = formats::node_cube(v, node);
  const Verdict verdict = judge((*frame.trace)(cube, cube.centre()), cube.depth);
  if (verdict == Verdict::split) return std::nullopt;
  return verdict;
}

TreeUpdate::Verdict TreeUpdate::judge(const LeafTrace& t, int depth) const {
  // The one leaf rule of C++ and GLSL (probebake/leaf_rule.h): the bake's placement rule.
  switch (gpu::leaf_verdict(t.hit_fraction, t.backface_fraction, depth, tree_->volume().info,
                            settings_.dead_backface_fraction)) {
  case gpu::LEAF_VERDICT_FREE: return Verdict::free;
  case gpu::LEAF_VERDICT_SPLIT: return Verdict::split;
  default: return Verdict::keep;
  }
}

void TreeUpdate::collapse(Frame& frame, int node, Verdict becomes) {
  const int light_out = queue_.other_kind_segment(kMemoryPullOffset);
  formats::ProbeVolume& v = tree_->volume();
  const int meta = v.octree[std::size_t(node)];
  float mean_sh[gpu::PROBE_SH_FLOATS] = {};
  int children_with_probes = 0;
  for (int octant = 0; octant < 8; ++octant) {
    const int child = formats::child_node(meta, octant);
    push(frame, light_out, child, gpu::LEAF_L0_PARENT_FREED);
    const int probe = tree_->probe_of(child);
    if (probe == kNoIndex) continue;
    for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k) mean_sh[k] += v.probes[std::size_t(probe)].irradiance_sh[k];
    ++children_with_probes;
    tree_->free_probe(probe);
    ++frame.stats.probes_freed;
  }
  tree_->collapse(node);
  ++frame.stats.collapses;
  push_parent(frame, queue_.same_kind_segment(kMemoryPullOffset), node, gpu::LEAF_M4_FREE_CLUSTER);
  if (becomes == Verdict::free) {
    push(frame, light_out, node, gpu::LEAF_L3_CHECK_BOXES);
    return;
  }
  // The merged leaf keeps a probe, starting from its children's mean (the eight probes freed above are
  // in the pool again, so this cannot run dry).
  const int probe = tree_->place_probe(node);
  for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k)
    v.probes[std::size_t(probe)].irradiance_sh[k] =
        children_with_probes > 0 ? mean_sh[k] / float(children_with_probes) : 0.0f;
  if (children_with_probes == 0 && *frame.initial)
    (*frame.initial)(v.probes[std::size_t(probe)].position, v.probes[std::size_t(probe)].irradiance_sh);
  place_surfels(frame, node);
  ++frame.stats.probes_placed;
  push(frame, light_out, node, gpu::LEAF_L1_PLACE_SURFELS);
}

// Gives the leaf's probe its surfel batches: lattice points [0, surfels_per_probe) in chained batches of
// SURFELS_PER_BATCH; L1 fills them (here they stay misses: the reference decides shape, not light).
void TreeUpdate::place_surfels(Frame& /*frame*/, int node) {
  const int probe = tree_->probe_of(node);
  const int total = tree_->volume().info.surfels_per_probe;
  for (int b = 0; b < batches_per_probe(); ++b) {
    const int batch = tree_->append_surfel_batch(probe);
    gpu::SurfelBatch& sb = tree_->volume().surfel_batches[std::size_t(batch)];
    sb.first = b * gpu::SURFELS_PER_BATCH;
    sb.count = std::min(gpu::SURFELS_PER_BATCH, total - sb.first);
  }
}

// ---- Light update transitions (thesis §3.2.2) ---------------------------------------------------------------

void TreeUpdate::light_update(Frame& frame) {
  const int pull = queue_.pull_segment(kLightPullOffset);
  const int memory_out = queue_.other_kind_segment(kLightPullOffset);
  const int light_out = queue_.same_kind_segment(kLightPullOffset);
  const std::vector<gpu::LeafEntry> entries = queue_.take(pull);
  const int budget = limit_or_all(settings_.max_light_entries, entries.size()); // leaves with a probe
  formats::ProbeVolume& v = tree_->volume();

  int traced = 0;
  for (const gpu::LeafEntry& e : entries) {
    if (e.state == gpu::LEAF_L0_PARENT_FREED) {
      ++frame.stats.processed[std::size_t(e.state)];
      continue;
    }
    if (!fits_state(e.node, e.state)) {
      ++frame.stats.stale_entries;
      continue;
    }
    const formats::NodeCube cube = formats::node_cube(v, e.node);
    const bool moved = touched(cube, frame.changed);
    const int probe = tree_->probe_of(e.node);
    if (probe != kNoIndex && traced++ >= budget) {
      // Deferred (L1/L2 trace and light; L3 only tests boxes and always runs). A leaf the boxes touched
      // waits as L1, so the change is measured when its turn comes.
      push(frame, light_out, e.node, moved ? gpu::LEAF_L1_PLACE_SURFELS : e.state);
      ++frame.stats.deferred;
      continue;
    }
    ++frame.stats.processed[std::size_t(e.state)];
    if (probe == kNoIndex) { // L3: only the boxes
      if (moved) {
        push(frame, memory_out, e.node, gpu::LEAF_M1_ALLOCATE_PROBE);
        push_parent(frame, memory_out, e.node, gpu::LEAF_M0_CHILD_ALLOCATING);
      } else {
        push(frame, light_out, e.node, gpu::LEAF_L3_CHECK_BOXES);
      }
      continue;
    }
    if (e.state == gpu::LEAF_L2_LIGHT && !moved) {
      push(frame, light_out, e.node, gpu::LEAF_L2_LIGHT);
      continue;
    }

    // L1: measure the leaf in the current pose and choose its next state.
    gpu::Probe& p = v.probes[std::size_t(probe)];
    const LeafTrace t = (*frame.trace)(cube, p.position);
    p.hit_fraction = t.hit_fraction;
    p.backface_fraction = t.backface_fraction;
    switch (judge(t, cube.depth)) {
    case Verdict::free: push(frame, memory_out, e.node, gpu::LEAF_M2_FREE_PROBE); break;
    case Verdict::split:
      push(frame, memory_out, e.node, gpu::LEAF_M3_SPLIT);
      push_parent(frame, memory_out, e.node, gpu::LEAF_M0_CHILD_ALLOCATING);
      break;
    case Verdict::keep:
      push(frame, light_out, e.node, gpu::LEAF_L2_LIGHT);
      // A leaf that changed and stays may have made its parent's split unnecessary: let it judge.
      push_parent(frame, memory_out, e.node, gpu::LEAF_M4_FREE_CLUSTER);
      break;
    }
  }
}

// ---- Consistency of queue and tree ---------------------------------------------------------------------------

std::vector<std::string> check_queue_covers_tree(const formats::ProbeVolume& v) {
  std::vector<std::string> problems;
  const int capacity = v.leaf_header.segment_capacity;
  std::unordered_map<int, int> state_of;
  for (int s = 0; s < 3; ++s) {
    for (int e = 0; e < v.leaf_header.count[s]; ++e) {
      const gpu::LeafEntry& entry = v.leaf_entries[std::size_t(s * capacity + e)];
      if (!state_of.emplace(entry.node, entry.state).second)
        problems.push_back("node " + std::to_string(entry.node) + " is queued twice");
    }
  }
  formats::for_each_leaf(v, [&](const formats::NodeCube& leaf) {
    const auto found = state_of.find(leaf.node);
    if (found == state_of.end()) {
      problems.push_back("leaf " + std::to_string(leaf.node) + " is in no segment");
      return;
    }
    const bool has_probe = v.octree[std::size_t(leaf.node)] < 0;
    const int s = found->second;
    const bool fits = has_probe ? (s == gpu::LEAF_M2_FREE_PROBE || s == gpu::LEAF_M3_SPLIT ||
                                   s == gpu::LEAF_L1_PLACE_SURFELS || s == gpu::LEAF_L2_LIGHT)
                                : (s == gpu::LEAF_M1_ALLOCATE_PROBE || s == gpu::LEAF_L3_CHECK_BOXES);
    if (!fits) problems.push_back("leaf " + std::to_string(leaf.node) + " is queued in state " + std::to_string(s));
    state_of.erase(found);
  });
  for (const auto& [node, state] : state_of) {
    const bool parent = is_live_node(v, node) && v.octree[std::size_t(node)] > 0;
    if (!parent || (state != gpu::LEAF_M0_CHILD_ALLOCATING && state != gpu::LEAF_M4_FREE_CLUSTER)) {
      problems.push_back("node " + std::to_string(node) + " queued in state " + std::to_string(state) +
                         " is not a leaf");
    }
  }
  return problems;
}

} // namespace probebake::dynamic
