// The leaf buffer's ring and set semantics (octree thesis §3.1.4, figure 3.3).
#include <gtest/gtest.h>

#include "probebake/dynamic/leaf_queue.h"
#include "probebake/formats/error.h"

namespace probebake::dynamic {
namespace {

formats::ProbeVolume volume_with_nodes(int nodes) {
  formats::ProbeVolume v;
  v.octree.assign(std::size_t(nodes), 0);
  return v;
}

TEST(LeafQueue, PullOriginCyclesLikeFigure3_3) {
  formats::ProbeVolume v = volume_with_nodes(10);
  LeafQueue q(v, 10);
  // Origins over three frames: 2, 1, 0, then again; MU pulls p, LU p + 1; pushes go to pull + 1 / + 2.
  const int expected_origin[] = {2, 1, 0, 2};
  for (int frame = 0; frame < 4; ++frame) {
    q.begin_frame();
    EXPECT_EQ(v.leaf_header.pull_origin, expected_origin[frame]);
    EXPECT_EQ(q.pull_segment(kMemoryPullOffset), expected_origin[frame]);
    EXPECT_EQ(q.pull_segment(kLightPullOffset), (expected_origin[frame] + 1) % 3);
    // What the light update pushes of its own kind is what it pulls next frame; memory likewise.
    const int next = (expected_origin[frame] + 2) % 3;
    EXPECT_EQ(q.same_kind_segment(kLightPullOffset), (next + kLightPullOffset) % 3);
    EXPECT_EQ(q.same_kind_segment(kMemoryPullOffset), (next + kMemoryPullOffset) % 3);
    EXPECT_EQ(q.other_kind_segment(kMemoryPullOffset), q.pull_segment(kLightPullOffset)); // same frame
    EXPECT_EQ(q.other_kind_segment(kLightPullOffset), (next + kMemoryPullOffset) % 3);
  }
}

TEST(LeafQueue, ANodeIsOneEntryPerSegmentWithTheStrongerState) {
  formats::ProbeVolume v = volume_with_nodes(10);
  LeafQueue q(v, 4);
  EXPECT_TRUE(q.push(0, 5, gpu::LEAF_M4_FREE_CLUSTER));
  EXPECT_TRUE(q.push(0, 5, gpu::LEAF_M0_CHILD_ALLOCATING)); // a child allocates: M0 wins
  EXPECT_TRUE(q.push(0, 5, gpu::LEAF_M4_FREE_CLUSTER));     // and stays
  EXPECT_TRUE(q.push(1, 3, gpu::LEAF_L3_CHECK_BOXES));
  EXPECT_TRUE(q.push(1, 3, gpu::LEAF_L0_PARENT_FREED)); // L0 overrides every light state
  EXPECT_TRUE(q.push(1, 3, gpu::LEAF_L1_PLACE_SURFELS));
  EXPECT_TRUE(q.push(1, 4, gpu::LEAF_L2_LIGHT));
  EXPECT_TRUE(q.push(1, 4, gpu::LEAF_L1_PLACE_SURFELS)); // L1 does L2's work and more
  ASSERT_EQ(q.count(0), 1);
  ASSERT_EQ(q.count(1), 2);
  EXPECT_EQ(q.entries(0)[0].state, gpu::LEAF_M0_CHILD_ALLOCATING);
  EXPECT_EQ(q.entries(1)[0].state, gpu::LEAF_L0_PARENT_FREED);
  EXPECT_EQ(q.entries(1)[1].state, gpu::LEAF_L1_PLACE_SURFELS);
  EXPECT_EQ(q.take(1).size(), 2u);
  EXPECT_EQ(q.count(1), 0);
  EXPECT_TRUE(q.push(1, 3, gpu::LEAF_L3_CHECK_BOXES)); // a fresh set after the pull
  EXPECT_EQ(q.entries(1)[0].state, gpu::LEAF_L3_CHECK_BOXES);
}

TEST(LeafQueue, AFullSegmentRefusesAndKeepsItsEntries) {
  formats::ProbeVolume v = volume_with_nodes(10);
  LeafQueue q(v, 2);
  EXPECT_TRUE(q.push(2, 1, gpu::LEAF_L2_LIGHT));
  EXPECT_TRUE(q.push(2, 2, gpu::LEAF_L2_LIGHT));
  EXPECT_FALSE(q.push(2, 3, gpu::LEAF_L2_LIGHT));
  EXPECT_TRUE(q.push(2, 2, gpu::LEAF_L1_PLACE_SURFELS)); // raising a present node needs no room
  EXPECT_EQ(q.count(2), 2);
}

TEST(LeafQueue, AStoredQueueIsCheckedAndItsSetsRebuilt) {
  formats::ProbeVolume v = volume_with_nodes(10);
  {
    LeafQueue q(v, 3);
    q.push(1, 7, gpu::LEAF_L3_CHECK_BOXES);
  }
  LeafQueue again(v, 3);
  EXPECT_TRUE(again.push(1, 7, gpu::LEAF_L1_PLACE_SURFELS));
  EXPECT_EQ(again.count(1), 1); // the stored entry was found, not duplicated
  v.leaf_entries[3 + 1] = gpu::LeafEntry{7, gpu::LEAF_L2_LIGHT};
  v.leaf_header.count[1] = 2;
  EXPECT_THROW(LeafQueue(v, 3), Error); // node 7 twice in segment 1
  v.leaf_header.count[1] = 1;
  v.leaf_entries[3].state = 42;
  EXPECT_THROW(LeafQueue(v, 3), Error);
}

} // namespace
} // namespace probebake::dynamic
