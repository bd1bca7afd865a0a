// Octree library: split/collapse/alloc/free on the thesis layout, free-list reuse, growth, point location,
// and thousands of random operations that must keep validate() clean.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

gpu::VolumeInfo settings(int max_depth) {
  gpu::VolumeInfo info{};
  info.root_min = glm::vec3(-8.0f, 0.0f, 2.0f);
  info.root_size = 16.0f;
  info.max_depth = max_depth;
  info.svo_depth = 0;
  info.surfels_per_probe = gpu::SURFELS_PER_BATCH; // batches below hold lattice points [0, count)
  info.split_low = 0.125f;
  info.split_high = 0.5f;
  return info;
}

std::string violations_text(const ValidationReport& report) {
  std::string text;
  for (const Violation& v : report.violations) text += format_violation(v) + "\n";
  return text;
}

void expect_valid(ProbeVolume& volume) {
  rebuild_probe_index(volume);
  const ValidationReport report = validate(volume);
  EXPECT_TRUE(report.valid()) << violations_text(report);
}

TEST(OctreeIndex, Arithmetic) {
  EXPECT_TRUE(is_node_index(0));
  EXPECT_TRUE(is_meta_index(1));
  EXPECT_TRUE(is_meta_index(10));
  EXPECT_FALSE(is_node_index(10));
  EXPECT_EQ(cluster_meta_of(2), 1);
  EXPECT_EQ(cluster_meta_of(9), 1);
  EXPECT_EQ(cluster_meta_of(11), 10);
  EXPECT_EQ(octant_of(18), 7);
  EXPECT_EQ(child_node(10, 3), 14);
  EXPECT_EQ(complete_clusters(1), 0u);
  EXPECT_EQ(complete_clusters(19), 2u);
  EXPECT_EQ(complete_clusters(23), 2u);
}

TEST(Octree, SplitPlaceCollapse) {
  ProbeVolume volume = make_empty_volume(settings(3));
  Octree tree(volume);
  const int root_probe = tree.place_probe(0);
  EXPECT_EQ(volume.octree[0], ~root_probe);
  EXPECT_EQ(volume.probes[root_probe].position, glm::vec3(0.0f, 8.0f, 10.0f));
  expect_valid(volume);

  const int meta = tree.split(0); // frees the root's probe: parents hold none
  ASSERT_NE(meta, kNoIndex);
  EXPECT_EQ(volume.octree[0], meta);
  EXPECT_EQ(volume.octree[meta], ~0);
  EXPECT_EQ(volume.probes[root_probe].link, 0);
  for (int octant = 0; octant < 8; ++octant) EXPECT_NE(tree.place_probe(child_node(meta, octant)), kNoIndex);
  expect_valid(volume);
  EXPECT_EQ(volume.probes[volume.octree[child_node(meta, 7)] ^ -1].depth, 1);

  EXPECT_FALSE(tree.collapse(0)); // children hold probes
  for (int octant = 0; octant < 8; ++octant) tree.free_probe(tree.probe_of(child_node(meta, octant)));
  EXPECT_TRUE(tree.collapse(0));
  EXPECT_EQ(volume.octree[0], 0);
  EXPECT_EQ(volume.octree[meta], 0);
  expect_valid(volume);
}

TEST(Octree, SplitStopsAtMaxDepth) {
  ProbeVolume volume = make_empty_volume(settings(1));
  Octree tree(volume);
  const int meta = tree.split(0);
  EXPECT_EQ(tree.split(child_node(meta, 0)), kNoIndex);
  expect_valid(volume);
}

TEST(Octree, MisuseThrows) {
  ProbeVolume volume = make_empty_volume(settings(2));
  Octree tree(volume);
  const int meta = tree.split(0);
  EXPECT_THROW(tree.split(0), Error);          // not a leaf
  EXPECT_THROW(tree.place_probe(meta), Error); // a meta index
  EXPECT_THROW(tree.collapse(child_node(meta, 1)), Error);
  EXPECT_THROW(tree.free_probe(0), Error); // not allocated
  EXPECT_THROW(tree.place_probe(1000), Error);
}

TEST(Octree, FreeListsReuseLastFreed) {
  ProbeVolume volume = make_empty_volume(settings(3));
  Octree tree(volume);
  const int meta = tree.split(0);
  const int a = tree.place_probe(child_node(meta, 0));
  const int b = tree.place_probe(child_node(meta, 1));
  EXPECT_EQ(a, 0);
  EXPECT_EQ(b, 1);
  tree.free_probe(a);
  EXPECT_EQ(tree.place_probe(child_node(meta, 2)), a);

  const int deeper = tree.split(child_node(meta, 3));
  ASSERT_TRUE(tree.collapse(child_node(meta, 3)));
  EXPECT_EQ(tree.split(child_node(meta, 4)), deeper);

  const int first = tree.append_surfel_batch(b);
  const int second = tree.append_surfel_batch(b);
  EXPECT_EQ(volume.probes[b].link, ~first);
  EXPECT_EQ(volume.surfel_batches[first].link, ~second);
  EXPECT_EQ(volume.surfel_batches[second].link, b + 1);
  tree.free_surfel_chain(b);
  EXPECT_EQ(volume.probes[b].link, ~gpu::PROBE_NO_SURFELS);
  EXPECT_EQ(tree.append_surfel_batch(b), second); // the chain is freed front to back: last freed, first reused
}

TEST(Octree, RebuiltFreeListsMatchTheBuffers) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  Octree tree(volume);
  int free_probes = 0, free_batches = 0;
  for (const gpu::Probe& p : volume.probes) free_probes += p.link == 0;
  for (const gpu::SurfelBatch& b : volume.surfel_batches) free_batches += b.link == 0;
  EXPECT_EQ(tree.free_probes(), free_probes);
  EXPECT_EQ(tree.free_batches(), free_batches);
  EXPECT_EQ(tree.free_clusters(), 1);
}

TEST(Octree, GrowthCompletesAnIncompleteTrailingCluster) {
  ProbeVolume volume = make_empty_volume(settings(4));
  volume.octree.resize(1 + 9 + 4, 0); // a buffer from elsewhere with an incomplete trailing cluster
  sync_info_counts(volume);
  expect_valid(volume);
  Octree tree(volume);
  EXPECT_EQ(tree.free_clusters(), 1);
  const int meta = tree.split(0);
  EXPECT_EQ(meta, 1);
  const int grown = tree.split(child_node(meta, 0));
  EXPECT_EQ(grown, 10); // the old incomplete cluster, completed
  EXPECT_EQ((volume.octree.size() - 1) % 9, 0u);
  EXPECT_EQ(volume.info.octree_elements, static_cast<int>(volume.octree.size()));
  expect_valid(volume);
}

TEST(Octree, FixedCapacityRefusesToGrow) {
  ProbeVolume volume = make_empty_volume(settings(4));
  Octree tree(volume, Octree::Growth::fixed);
  EXPECT_EQ(tree.split(0), kNoIndex);
  EXPECT_EQ(tree.place_probe(0), kNoIndex);
  tree.reserve_clusters(1);
  tree.reserve_probes(1);
  EXPECT_EQ(tree.place_probe(0), 0);
  const int meta = tree.split(0);
  EXPECT_EQ(meta, 1);
  EXPECT_EQ(tree.split(child_node(meta, 0)), kNoIndex);
  EXPECT_EQ(tree.place_probe(child_node(meta, 0)), 0); // the root's probe was freed by the split
  EXPECT_EQ(tree.place_probe(child_node(meta, 1)), kNoIndex);
  expect_valid(volume);
}

TEST(Octree, NodeCubeAndFindLeaf) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  int leaves = 0;
  for_each_leaf(volume, [&](const NodeCube& leaf) {
    ++leaves;
    const NodeCube climbed = node_cube(volume, leaf.node);
    EXPECT_EQ(climbed.min, leaf.min);
    EXPECT_EQ(climbed.size, leaf.size);
    EXPECT_EQ(climbed.depth, leaf.depth);
    const std::optional<NodeCube> found = find_leaf(volume, leaf.centre());
    ASSERT_TRUE(found);
    EXPECT_EQ(found->node, leaf.node);
    const std::optional<NodeCube> at_min = find_leaf(volume, leaf.min);
    ASSERT_TRUE(at_min);
    EXPECT_EQ(at_min->node, leaf.node); // cubes are half-open: the minimum corner belongs to the cube
  });
  EXPECT_EQ(leaves, 29);
  const glm::vec3 max_corner = volume.info.root_min + glm::vec3(volume.info.root_size);
  ASSERT_TRUE(find_leaf(volume, max_corner)); // the root's maximum faces belong to it
  EXPECT_FALSE(find_leaf(volume, max_corner + glm::vec3(0.001f, 0.0f, 0.0f)));
  EXPECT_FALSE(find_leaf(volume, glm::vec3(std::nanf(""), 0.0f, 0.0f)));
}

TEST(Octree, WalkRefusesACycle) {
  ProbeVolume volume = testing::make_sample(testing::Sample::small);
  const int meta = volume.octree[0];
  volume.octree[child_node(meta, 1)] = meta; // a node pointing at its own cluster
  EXPECT_THROW(for_each_leaf(volume, [](const NodeCube&) {}), Error);
}

// Random split / collapse / place / free / surfel operations; validate() after every batch of 100.
TEST(Octree, RandomOperationsStayValid) {
  ProbeVolume volume = make_empty_volume(settings(5));
  Octree tree(volume);
  std::mt19937 rng(12345);
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  int operations = 0;
  for (int round = 0; round < 60; ++round) {
    for (int step = 0; step < 100; ++step, ++operations) {
      std::vector<NodeCube> leaves;
      for_each_leaf(volume, [&](const NodeCube& leaf) { leaves.push_back(leaf); });
      const NodeCube& leaf = leaves[pick(leaves.size())];
      const int action = static_cast<int>(rng() % 10);
      if (action < 3 && leaves.size() < 400) {
        tree.split(leaf.node);
      } else if (action < 5 && leaf.node != 0) {
        const int parent = ~volume.octree[cluster_meta_of(leaf.node)];
        const int meta = volume.octree[parent];
        for (int octant = 0; octant < 8; ++octant) {
          if (const int p = tree.probe_of(child_node(meta, octant)); p != kNoIndex) tree.free_probe(p);
        }
        bool all_leaves = true;
        for (int octant = 0; octant < 8; ++octant)
          all_leaves = all_leaves && volume.octree[child_node(meta, octant)] == 0;
        EXPECT_EQ(tree.collapse(parent), all_leaves);
      } else if (action < 7 && volume.octree[leaf.node] == 0) {
        ASSERT_NE(tree.place_probe(leaf.node), kNoIndex);
      } else if (action < 8 && volume.octree[leaf.node] < 0) {
        tree.free_probe(tree.probe_of(leaf.node));
      } else if (action < 9 && volume.octree[leaf.node] < 0) {
        const int batch = tree.append_surfel_batch(tree.probe_of(leaf.node));
        volume.surfel_batches[batch].count = 1 + static_cast<int>(rng() % gpu::SURFELS_PER_BATCH);
      } else if (volume.octree[leaf.node] < 0) {
        tree.free_surfel_chain(tree.probe_of(leaf.node));
      }
    }
    expect_valid(volume);
    if (HasFailure()) break;
  }
  EXPECT_EQ(operations, 6000);
  // Free lists rebuilt from the buffers agree with the incrementally kept ones.
  const int clusters = tree.free_clusters(), probes = tree.free_probes(), batches = tree.free_batches();
  tree.rebuild_free_lists();
  EXPECT_EQ(tree.free_clusters(), clusters);
  EXPECT_EQ(tree.free_probes(), probes);
  EXPECT_EQ(tree.free_batches(), batches);
}

} // namespace
} // namespace probebake::formats
