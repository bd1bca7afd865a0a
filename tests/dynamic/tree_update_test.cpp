// The dynamic octree's CPU reference (thesis §3.2.1-3.2.2 with the departures listed in tree_update.h):
// analytic scenes where the answer is known (a leaf "sees" geometry exactly when its cube overlaps a moving
// box), round trips of motion that must leave the pools as they were, and a soak of random motion with the
// validator and the queue-covers-tree check after every frame.
#include <algorithm>
#include <cmath>
#include <random>
#include <optional>
#include <set>
#include <tuple>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include "probebake/dynamic/tree_update.h"
#include "probebake/formats/validate.h"

namespace probebake::dynamic {
namespace {

constexpr float kRootSize = 8.0f;

struct Pools {
  int clusters = 200, probes = 600, batches = 1200;
};

// An octree volume of root [0, 8)^3 with an empty root leaf and fixed pools, like the runtime's buffers.
struct World {
  formats::ProbeVolume volume;
  formats::Octree tree;
  TreeUpdate update;
  std::vector<Box> objects;

  World(int max_depth, Pools pools, TreeUpdateSettings settings = {})
      : volume(make_volume(max_depth)), tree(reserve(volume, pools)), update(tree, settings) {}

  static formats::ProbeVolume make_volume(int max_depth) {
    gpu::VolumeInfo info{};
    info.root_size = kRootSize;
    info.placement = gpu::PLACEMENT_OCTREE;
    info.max_depth = max_depth;
    info.svo_depth = max_depth;
    info.surfels_per_probe = 24; // two surfel batches per probe
    info.split_low = 0.05f;
    info.split_high = 0.5f;
    formats::ProbeVolume v = formats::make_empty_volume(info);
    v.surfel_batches.resize(1); // a batch pool exists (Octree grows it below)
    formats::sync_info_counts(v);
    return v;
  }
  static formats::ProbeVolume& reserve(formats::ProbeVolume& v, Pools pools) {
    formats::Octree grow(v, formats::Octree::Growth::automatic);
    grow.reserve_clusters(pools.clusters);
    grow.reserve_probes(pools.probes);
    grow.reserve_batches(pools.batches);
    return v;
  }

  // A leaf sees geometry (every lattice ray hits inside its cube) when its cube overlaps an object; a
  // static floor slab (when set) gives the cubes it overlaps a hit fraction between the thresholds.
  LeafTrace trace(const formats::NodeCube& cube, glm::vec3) const {
    auto overlaps = [&](const Box& b) {
      bool overlap = true;
      for (int a = 0; a < 3; ++a) overlap &= b.max[a] > cube.min[a] && b.min[a] < cube.min[a] + cube.size;
      return overlap;
    };
    if (std::any_of(objects.begin(), objects.end(), overlaps)) return {1.0f, 0.0f};
    if (floor && overlaps(*floor)) return {0.3f, 0.0f}; // in [split_low, split_high): keep, do not split
    return {0.0f, 0.0f};
  }
  std::optional<Box> floor;

  TreeFrameStats frame(std::span<const Box> changed) {
    const TreeFrameStats stats =
        update.run_frame(changed, [this](const formats::NodeCube& c, glm::vec3 p) { return trace(c, p); });
    formats::rebuild_probe_index(volume); // the runtime's probe-index pass
    return stats;
  }

  // Moves the objects to `to`: one frame with the union of old and new boxes as changed regions.
  TreeFrameStats move(std::vector<Box> to) {
    std::vector<Box> changed;
    for (std::size_t i = 0; i < std::max(to.size(), objects.size()); ++i) {
      Box u = i < to.size() ? to[i] : objects[i];
      if (i < objects.size()) u = Box{glm::min(u.min, objects[i].min), glm::max(u.max, objects[i].max)};
      changed.push_back(u);
    }
    objects = std::move(to);
    return frame(changed);
  }

  // Idle frames until no memory state or L1 is processed twice in a row; returns the frames it took.
  int settle(int max_frames = 100) {
    int quiet = 0;
    for (int f = 1; f <= max_frames; ++f) {
      const TreeFrameStats s = frame({});
      const bool busy = s.processed[gpu::LEAF_L1_PLACE_SURFELS] > 0 ||
                        std::any_of(s.processed.begin(), s.processed.begin() + gpu::LEAF_L0_PARENT_FREED,
                                    [](int n) { return n > 0; });
      quiet = busy ? 0 : quiet + 1;
      if (quiet == 2) return f;
    }
    return -1;
  }
};

// The tree as a set of leaves (depth, integer corner, has probe): independent of buffer indices.
using Leaf = std::tuple<int, int, int, int, bool>;
std::set<Leaf> shape(const formats::ProbeVolume& v) {
  std::set<Leaf> leaves;
  formats::for_each_leaf(v, [&](const formats::NodeCube& c) {
    const glm::vec3 i = c.min / c.size;
    leaves.emplace(c.depth, int(std::lround(i.x)), int(std::lround(i.y)), int(std::lround(i.z)),
                   v.octree[std::size_t(c.node)] < 0);
  });
  return leaves;
}

int probes_in(const std::set<Leaf>& leaves) {
  return int(std::count_if(leaves.begin(), leaves.end(), [](const Leaf& l) { return std::get<4>(l); }));
}

void expect_consistent(const World& w, const TreeFrameStats& s, int frame, bool validate = true) {
  const formats::ValidationReport report = validate ? formats::validate(w.volume) : formats::ValidationReport{};
  ASSERT_TRUE(report.valid()) << "frame " << frame << ": " << report.violations.front().invariant << ": "
                              << report.violations.front().message;
  const std::vector<std::string> problems = check_queue_covers_tree(w.volume);
  ASSERT_TRUE(problems.empty()) << "frame " << frame << ": " << problems.front();
  ASSERT_EQ(s.lost_entries, 0) << "frame " << frame;
  ASSERT_EQ(s.stale_entries, 0) << "frame " << frame;
}

TEST(TreeUpdate, AnObjectEnteringEmptySpaceSplitsItsCubesToMaxDepth) {
  World w(3, {});
  const Box object{{1.1f, 1.1f, 1.1f}, {2.9f, 2.9f, 2.9f}}; // overlaps the unit cubes 1..2 on each axis
  const TreeFrameStats first = w.move({object});
  expect_consistent(w, first, 1);
  ASSERT_GT(w.settle(), 0);
  const std::set<Leaf> leaves = shape(w.volume);
  // Depth 3 cubes are 1 m: exactly the 8 overlapping ones hold probes, every other leaf is empty.
  EXPECT_EQ(probes_in(leaves), 8);
  for (const Leaf& l : leaves) {
    if (!std::get<4>(l)) continue;
    EXPECT_EQ(std::get<0>(l), 3);
    for (const int c : {std::get<1>(l), std::get<2>(l), std::get<3>(l)}) EXPECT_TRUE(c == 1 || c == 2);
  }
  // Clusters: the root's children, those of the depth-1 cube [0, 4)^3, and those of the eight depth-2
  // cubes (2 m) that the object overlaps: 1 + 1 + 8.
  EXPECT_EQ(200 - w.tree.free_clusters(), 10);
  EXPECT_EQ(600 - w.tree.free_probes(), 8);
  EXPECT_EQ(1200 - w.tree.free_batches(), 16);
}

TEST(TreeUpdate, LeavingMergesBackAndTheRoundTripReturnsEveryPoolElement) {
  World w(4, {});
  const Box a{{0.6f, 0.6f, 0.6f}, {1.4f, 1.9f, 1.2f}};
  const Box b{{5.2f, 4.4f, 6.1f}, {6.7f, 5.3f, 6.6f}};
  w.move({a});
  ASSERT_GT(w.settle(), 0);
  const std::set<Leaf> at_a = shape(w.volume);
  const int clusters = w.tree.free_clusters(), probes = w.tree.free_probes(), batches = w.tree.free_batches();

  w.move({b});
  ASSERT_GT(w.settle(), 0);
  const std::set<Leaf> at_b = shape(w.volume);
  EXPECT_NE(at_a, at_b);
  for (const Leaf& l : at_b) { // nothing is left where the object was: every probe's cube reaches x > 5
    if (std::get<4>(l)) {
      EXPECT_GT(float(std::get<1>(l) + 1) * kRootSize / std::pow(2.0f, float(std::get<0>(l))), 5.0f)
          << "probe left behind";
    }
  }
  w.move({a});
  ASSERT_GT(w.settle(), 0);
  EXPECT_EQ(shape(w.volume), at_a);
  EXPECT_EQ(w.tree.free_clusters(), clusters);
  EXPECT_EQ(w.tree.free_probes(), probes);
  EXPECT_EQ(w.tree.free_batches(), batches);

  w.move({});
  ASSERT_GT(w.settle(), 0);
  EXPECT_EQ(shape(w.volume), (std::set<Leaf>{{0, 0, 0, 0, false}})); // back to the empty root
  EXPECT_EQ(w.tree.free_clusters(), 200);
}

// The validator's leaf-queue rule: M0/M4 name parents, every other state a leaf.
TEST(TreeUpdate, TheValidatorKnowsWhichStatesNameParents) {
  World w(3, {});
  w.move({Box{{0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f}}});
  ASSERT_GT(w.settle(), 0);
  ASSERT_TRUE(formats::validate(w.volume).valid());
  formats::ProbeVolume parent_as_leaf = w.volume, leaf_as_parent = w.volume;
  const int segment = 0, capacity = w.volume.leaf_header.segment_capacity;
  for (formats::ProbeVolume* v : {&parent_as_leaf, &leaf_as_parent}) {
    std::fill_n(v->leaf_entries.begin(), 3 * capacity, gpu::LeafEntry{});
    v->leaf_header.count[0] = v->leaf_header.count[1] = v->leaf_header.count[2] = 0;
    v->leaf_header.count[segment] = 1;
  }
  parent_as_leaf.leaf_entries[0] = {0, gpu::LEAF_L2_LIGHT}; // the root is a parent
  leaf_as_parent.leaf_entries[0] = {formats::child_node(w.volume.octree[0], 7), gpu::LEAF_M4_FREE_CLUSTER}; // a leaf
  for (const formats::ProbeVolume* v : {&parent_as_leaf, &leaf_as_parent}) {
    const formats::ValidationReport r = formats::validate(*v);
    ASSERT_EQ(r.violations.size(), 1u);
    EXPECT_EQ(r.violations[0].invariant, "leaf_entry_node");
  }
  leaf_as_parent.leaf_entries[0].node = 0; // M4 on the root: a parent, fine
  EXPECT_TRUE(formats::validate(leaf_as_parent).valid());
}

// An object crossing the floor splits the floor's cubes; when it has gone, the children on the floor still
// hold probes (they see the floor), and the thesis's M4 would keep the split for good. Here the parent
// judges itself and merges, so the floor's tree is the one it had before the object came.
TEST(TreeUpdate, MergingMirrorsSplittingWhereChildrenStillSeeStaticGeometry) {
  World w(3, {});
  w.floor = Box{{0.0f, 0.0f, 0.0f}, {8.0f, 0.5f, 8.0f}};
  w.move({Box{{0.0f, 0.0f, 0.0f}, {8.0f, 8.0f, 8.0f}}}); // a frame that touches everything: grow from the root
  w.objects.clear();
  ASSERT_GT(w.settle(), 0);
  const std::set<Leaf> before = shape(w.volume);
  const int clusters = w.tree.free_clusters(), probes = w.tree.free_probes();
  EXPECT_EQ(before, (std::set<Leaf>{{0, 0, 0, 0, true}})); // the root sees the floor at 0.3: one probe

  w.move({Box{{1.2f, 0.2f, 1.2f}, {2.3f, 1.4f, 2.6f}}});
  ASSERT_GT(w.settle(), 0);
  EXPECT_GT(probes_in(shape(w.volume)), 8);
  w.move({});
  ASSERT_GT(w.settle(), 0);
  EXPECT_EQ(shape(w.volume), before);
  EXPECT_EQ(w.tree.free_clusters(), clusters);
  EXPECT_EQ(w.tree.free_probes(), probes);
}

TEST(TreeUpdate, NewProbesStartFromTheirParentsOrTheSamplersIrradiance) {
  World w(2, {});
  const Box object{{0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f}};
  w.objects = {object};
  // Frame 1: the root (no probe, touched) asks for a probe; frame 2 places it from the sampler's answer.
  const auto sampler = [](glm::vec3 p, float(&sh)[gpu::PROBE_SH_FLOATS]) {
    std::fill(std::begin(sh), std::end(sh), 0.0f);
    sh[0] = p.x;
  };
  const auto trace = [&w](const formats::NodeCube& c, glm::vec3 p) { return w.trace(c, p); };
  w.update.run_frame(std::span<const Box>(&object, 1), trace, sampler);
  w.update.run_frame({}, trace, sampler);
  const int root_probe = w.tree.probe_of(0);
  ASSERT_NE(root_probe, formats::kNoIndex);
  EXPECT_EQ(w.volume.probes[std::size_t(root_probe)].irradiance_sh[0], 4.0f); // the root cube's centre x
  w.volume.probes[std::size_t(root_probe)].irradiance_sh[4] = 7.0f;
  w.update.run_frame({}, trace, sampler); // L1 measured f = 1 in frame 2: the root splits now
  ASSERT_FALSE(w.tree.is_leaf(0));
  const int meta = w.volume.octree[0];
  for (int octant = 0; octant < 8; ++octant) {
    const int probe = w.tree.probe_of(formats::child_node(meta, octant));
    ASSERT_NE(probe, formats::kNoIndex);
    EXPECT_EQ(w.volume.probes[std::size_t(probe)].irradiance_sh[0], 4.0f);
    EXPECT_EQ(w.volume.probes[std::size_t(probe)].irradiance_sh[4], 7.0f);
  }
}

TEST(TreeUpdate, DryPoolsKeepTheTreeValidCountTheShortfallAndRecover) {
  World w(4, {.clusters = 4, .probes = 20, .batches = 40});
  int failed = 0;
  for (int f = 0; f < 40; ++f) {
    const TreeFrameStats s = f == 0 ? w.move({Box{{0.2f, 0.2f, 0.2f}, {3.7f, 3.7f, 3.7f}}}) : w.frame({});
    expect_consistent(w, s, f);
    failed += s.failed_allocations;
  }
  EXPECT_GT(failed, 0);
  EXPECT_LE(w.tree.free_probes(), 20);
  w.move({});
  ASSERT_GT(w.settle(), 0);
  EXPECT_EQ(w.tree.free_clusters(), 4);
  EXPECT_EQ(w.tree.free_probes(), 20);
  EXPECT_EQ(w.tree.free_batches(), 40);
}

// Random motion of three boxes with random per-frame limits; every frame valid; the motion returns to its
// start and so must the tree and the pools.
TEST(TreeUpdate, SoakOfRandomMotionStaysValidAndLeaksNothing) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> coord(0.0f, kRootSize), extent(0.2f, 2.5f);
  std::uniform_int_distribution<int> limit(0, 12);
  TreeUpdateSettings settings;
  World w(4, {.clusters = 2000, .probes = 8000, .batches = 16000}, settings);
  auto random_box = [&] {
    const glm::vec3 lo(coord(rng), coord(rng), coord(rng));
    return Box{lo, glm::min(lo + glm::vec3(extent(rng), extent(rng), extent(rng)), glm::vec3(kRootSize))};
  };
  const std::vector<Box> start{random_box(), random_box(), random_box()};
  w.move(start);
  ASSERT_GT(w.settle(), 0);
  const std::set<Leaf> start_shape = shape(w.volume);
  const int clusters = w.tree.free_clusters(), probes = w.tree.free_probes();

  int max_live = 0;
  for (int f = 0; f < 1500; ++f) {
    w.update.set_settings({.max_memory_entries = limit(rng), .max_light_entries = limit(rng) * 4});
    std::vector<Box> next = w.objects;
    next[std::size_t(f % 3)] =
        f % 7 == 0 ? random_box()
                   : Box{next[f % 3].min + 0.05f, glm::min(next[f % 3].max + 0.05f, glm::vec3(kRootSize))};
    const TreeFrameStats s = w.move(next);
    expect_consistent(w, s, f, f % 5 == 0); // the full validator every 5th frame, the queue check always
    ASSERT_EQ(s.failed_allocations, 0);
    max_live = std::max(max_live, 8000 - w.tree.free_probes());
  }
  w.update.set_settings(settings);
  w.move(start);
  ASSERT_GT(w.settle(200), 0);
  EXPECT_EQ(shape(w.volume), start_shape);
  EXPECT_EQ(w.tree.free_clusters(), clusters);
  EXPECT_EQ(w.tree.free_probes(), probes);
  EXPECT_LE(max_live, 3 * 4096); // three objects at depth 4 (0.5 m cubes) cannot need more
  for (const gpu::Probe& p : w.volume.probes) {
    for (const float c : p.irradiance_sh) ASSERT_TRUE(std::isfinite(c));
  }
}

} // namespace
} // namespace probebake::dynamic
