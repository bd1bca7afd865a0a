// The GPU memory update and light transitions (runtime/memory_update/)
// against the CPU reference dynamic::TreeUpdate: the same scripted frames (changed boxes, max depth raised
// from 1 to 3 and lowered back) must give the same tree, the same probes and the same queue states; and a
// soak of random inputs must keep the live volume valid, leak nothing and stay bounded.
// The CPU side and the canonical comparison are in memory_reference.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/bake/bake.h"
#include "probebake/scene/scene.h"
#include "probebake/dynamic/tree_update.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/scenes.h"
#include "memory_reference.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using MemoryUpdateTest = RuntimeTest;

// Frame after which the bake's depth-1 tree has settled under the runtime's rule (the bake's placement also
// refines towards triangles its centre cannot see, so the runtime frees a few probes in frame 2).
constexpr int kSettledAtDepth1 = 4;

// Refine to max depth 3, move boxes through the room, then back to max depth 1.
std::vector<Step> scripted_steps(const formats::ProbeVolume& v) {
  const runtime::Box all = root_box(v);
  const glm::vec3 lo = v.info.root_min, size(v.info.root_size);
  std::vector<Step> steps;
  steps.push_back({{all}, std::nullopt}); // re-measure at the bake's depth 1
  for (int f = 0; f < 3; ++f) steps.push_back({});
  steps.push_back({{all}, 3});
  for (int f = 0; f < 8; ++f) steps.push_back({});
  steps.push_back({{{lo + 0.2f * size, lo + 0.45f * size}}, std::nullopt});
  steps.push_back({{{lo + 0.5f * size, lo + 0.9f * size}}, std::nullopt});
  for (int f = 0; f < 3; ++f) steps.push_back({});
  steps.push_back({{all}, 1});
  for (int f = 0; f < 10; ++f) steps.push_back({});
  return steps;
}

// Back at depth 1 the tree merged back to the settled one, and the batch and cluster pools' use with it.
void expect_merged_back(const Canonical& back, const Canonical& settled) {
  EXPECT_EQ(back.leaves, settled.leaves);
  EXPECT_EQ(back.batches, settled.batches);
  EXPECT_EQ(back.clusters, settled.clusters);
}

TEST_F(MemoryUpdateTest, GpuAndCpuGrowAndShrinkTheSameTree) {
  auto gpu = runtime::Volume::upload(context(), shallow_cornell(), dynamic_options());
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  auto start = gpu.value().read_back();
  ASSERT_TRUE(start.ok()) << start.status().message;
  Cpu cpu(start.value());
  const Canonical at_start = canonical(start.value());

  int frame = 0, most_probes = 0, splits = 0, collapses = 0;
  Canonical settled;
  for (const Step& step : scripted_steps(start.value())) {
    ++frame;
    runtime::FrameInputs in;
    in.changed_boxes = step.boxes;
    in.max_depth = step.max_depth;
    auto stats = gpu.value().run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    const dynamic::TreeFrameStats cpu_stats = cpu.frame(step);
    expect_same_stats(stats.value().memory, cpu_stats, frame);
    // The light update lights exactly the leaves its transitions took (L1, L2), not every slot.
    const runtime::MemoryUpdateStats& m = stats.value().memory;
    EXPECT_EQ(stats.value().light.lit_probes, m.processed[gpu::LEAF_L1_PLACE_SURFELS] + m.processed[gpu::LEAF_L2_LIGHT])
        << "frame " << frame;
    auto live = gpu.value().read_back();
    ASSERT_TRUE(live.ok()) << live.status().message;
    const Canonical g = canonical(live.value()), c = canonical(cpu.volume);
    const std::string difference = first_difference(g, c);
    if (!difference.empty()) {
      formats::for_each_leaf(live.value(), [&](const formats::NodeCube& leaf) {
        const int value = live.value().octree[std::size_t(leaf.node)];
        if (value >= 0) return;
        const gpu::Probe& p = live.value().probes[std::size_t(~value)];
        const dynamic::LeafTrace t = measure(live.value(), leaf);
        if (p.hit_fraction != t.hit_fraction || p.backface_fraction != t.backface_fraction)
          std::printf("[memory] leaf %s (depth %d) measured differently: GPU f %g b %g, CPU f %g b %g\n",
                      path_of(live.value(), leaf.node)->c_str(), leaf.depth, p.hit_fraction, p.backface_fraction,
                      t.hit_fraction, t.backface_fraction);
      });
    }
    ASSERT_EQ(difference, "") << "frame " << frame;
    EXPECT_EQ(stats.value().memory.free_probes, cpu.tree.free_probes()) << "frame " << frame;
    EXPECT_EQ(stats.value().memory.free_batches, cpu.tree.free_batches()) << "frame " << frame;
    EXPECT_EQ(stats.value().memory.free_clusters, cpu.tree.free_clusters()) << "frame " << frame;
    const std::vector<std::string> problems = dynamic::check_queue_covers_tree(live.value());
    ASSERT_TRUE(problems.empty()) << "frame " << frame << ": " << problems.front();
    expect_valid(live.value(), 3, frame);
    if (frame == kSettledAtDepth1) settled = g;
    most_probes = std::max(most_probes, g.probes);
    splits += stats.value().memory.splits;
    collapses += stats.value().memory.collapses;
  }
  const Canonical end = canonical(cpu.volume);
  std::printf("[memory] %d frames: probes %d baked at depth 1, %d settled, %d at most (depth 3), %d back at depth 1; "
              "%d splits, %d merges; pool use settled %d/%d/%d (probes/batches/clusters), at the end %d/%d/%d\n",
              frame, at_start.probes, settled.probes, most_probes, end.probes, splits, collapses, settled.probes,
              settled.batches, settled.clusters, end.probes, end.batches, end.clusters);
  EXPECT_GT(most_probes, 2 * settled.probes); // depth 3 refined the tree
  EXPECT_GT(splits, 0);
  EXPECT_GT(collapses, 0);
  // Everything merged back: the settled tree and its pool use, element for element.
  expect_merged_back(end, settled);
  EXPECT_EQ(end.probes, settled.probes);
}

// No NaN or Inf in what the memory update writes or the light update reads back into the probes.
void expect_finite_probes(const formats::ProbeVolume& v, int frame) {
  for (std::size_t i = 0; i < v.probes.size(); ++i) {
    const gpu::Probe& p = v.probes[i];
    bool finite = std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z) &&
                  std::isfinite(p.hit_fraction) && std::isfinite(p.backface_fraction);
    for (float c : p.irradiance_sh) finite = finite && std::isfinite(c);
    ASSERT_TRUE(finite) << "frame " << frame << ": probe " << i;
  }
}

// Runs idle frames with every leaf re-measured until no memory work is left; returns the frames it took.
int settle(runtime::Volume& gpu, const runtime::Box& all, std::optional<int> max_depth) {
  for (int f = 1; f <= 60; ++f) {
    runtime::FrameInputs in;
    if (f <= 2) in.changed_boxes = {all};
    if (f == 1) in.max_depth = max_depth;
    auto stats = gpu.run_frame(in);
    EXPECT_TRUE(stats.ok()) << stats.status().message;
    if (!stats.ok()) return -1;
    const runtime::MemoryUpdateStats& m = stats.value().memory;
    const bool busy = m.splits + m.collapses + m.probes_placed + m.probes_freed + m.deferred > 0 ||
                      m.processed[std::size_t(gpu::LEAF_L1_PLACE_SURFELS)] > 0;
    if (f > 3 && !busy) return f;
  }
  return -1;
}

// Hundreds of frames of random boxes, max depths 1-3 and per-frame limits: the live volume is read back and
// checked every K frames; back at the start (depth 1, re-measured), the tree and every pool are as they were.
TEST_F(MemoryUpdateTest, SoakOfRandomBoxesAndDepthsStaysValidAndLeaksNothing) {
  constexpr int kFrames = 300, kCheckEvery = 10;
  auto gpu = runtime::Volume::upload(context(), shallow_cornell(), dynamic_options());
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  const formats::ProbeVolume start = gpu.value().read_back().value();
  const runtime::Box all = root_box(start);
  ASSERT_GT(settle(gpu.value(), all, std::nullopt), 0);
  const Canonical settled = canonical(gpu.value().read_back().value());

  std::mt19937 random(12);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int most_probes = 0, deferred = 0, splits = 0, collapses = 0, checks = 0;
  for (int frame = 1; frame <= kFrames; ++frame) {
    runtime::FrameInputs in;
    for (int b = 0; b < 3; ++b) {
      if (unit(random) < 0.5f) continue;
      const glm::vec3 centre = all.min + (all.max - all.min) * glm::vec3(unit(random), unit(random), unit(random));
      const glm::vec3 half = (all.max - all.min) * (0.02f + 0.2f * unit(random));
      in.changed_boxes.push_back({centre - half, centre + half});
    }
    if (unit(random) < 0.05f) in.max_depth = 1 + int(unit(random) * 2.999f);
    if (frame > kFrames / 2) in.limits = {4, 40}; // the second half defers work
    auto stats = gpu.value().run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    const runtime::MemoryUpdateStats& m = stats.value().memory;
    ASSERT_EQ(m.lost_entries, 0) << "frame " << frame;
    deferred += m.deferred;
    splits += m.splits;
    collapses += m.collapses;
    if (frame % kCheckEvery != 0) continue;
    const formats::ProbeVolume live = gpu.value().read_back().value();
    expect_valid(live, 3, frame);
    expect_finite_probes(live, frame);
    const std::vector<std::string> problems = dynamic::check_queue_covers_tree(live);
    ASSERT_TRUE(problems.empty()) << "frame " << frame << ": " << problems.front();
    const int probes = live_probe_count(live);
    ASSERT_LE(probes, 1 + 8 + 64 + 512) << "frame " << frame; // the leaves of a depth-3 tree, at most
    ASSERT_EQ(probes + m.free_probes, m.probe_capacity) << "frame " << frame;
    most_probes = std::max(most_probes, probes);
    ++checks;
  }
  const int settle_frames = settle(gpu.value(), all, 1);
  ASSERT_GT(settle_frames, 0);
  const formats::ProbeVolume end = gpu.value().read_back().value();
  ASSERT_TRUE(gpu.value().validate_live().ok());
  const Canonical back = canonical(end);
  std::printf(
      "[memory] soak: %d frames, %d checks, at most %d probes, %d splits, %d merges, %d deferred; back at depth 1 "
      "after %d frames: %d probes (settled start %d), pools %d/%d/%d (start %d/%d/%d)\n",
      kFrames, checks, most_probes, splits, collapses, deferred, settle_frames, back.probes, settled.probes,
      back.probes, back.batches, back.clusters, settled.probes, settled.batches, settled.clusters);
  EXPECT_GT(splits, 10);
  EXPECT_GT(collapses, 10);
  EXPECT_GT(deferred, 0);
  expect_merged_back(back, settled);
  EXPECT_EQ(back.probes, settled.probes);
}

// Pools smaller than the refinement asks for: allocations fail and are counted, the nodes keep their states,
// nothing is corrupted, and lowering the depth again returns every element.
TEST_F(MemoryUpdateTest, DryPoolsCountTheShortfallAndCorruptNothing) {
  runtime::UploadOptions options = dynamic_options();
  options.pools = {3, 30, 90};
  auto gpu = runtime::Volume::upload(context(), shallow_cornell(), options);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  const runtime::Box all = root_box(shallow_cornell());
  ASSERT_GT(settle(gpu.value(), all, std::nullopt), 0);
  const Canonical settled = canonical(gpu.value().read_back().value());
  int failed = 0;
  for (int frame = 1; frame <= 12; ++frame) {
    runtime::FrameInputs in;
    in.changed_boxes = {all};
    if (frame == 1) in.max_depth = 3;
    auto stats = gpu.value().run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    failed += stats.value().memory.failed_allocations;
    const formats::ProbeVolume live = gpu.value().read_back().value();
    expect_valid(live, 3, frame);
    const std::vector<std::string> problems = dynamic::check_queue_covers_tree(live);
    ASSERT_TRUE(problems.empty()) << "frame " << frame << ": " << problems.front();
    EXPECT_GE(stats.value().memory.free_probes, 0);
    EXPECT_GE(stats.value().memory.free_clusters, 0);
  }
  EXPECT_GT(failed, 0);
  ASSERT_GT(settle(gpu.value(), all, 1), 0);
  const Canonical back = canonical(gpu.value().read_back().value());
  std::printf("[memory] dry pools (3 clusters, 30 probes, 90 batches free): %d failed allocations; back at depth 1: "
              "%d/%d/%d vs %d/%d/%d\n",
              failed, back.probes, back.batches, back.clusters, settled.probes, settled.batches, settled.clusters);
  expect_merged_back(back, settled);
}

TEST_F(MemoryUpdateTest, FrameInputsOutOfRangeAreInvalidArguments) {
  auto gpu = runtime::Volume::upload(context(), shallow_cornell(), dynamic_options());
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<runtime::FrameInputs> bad(7);
  bad[0].changed_boxes = {{glm::vec3(0.0f), glm::vec3(nan)}};
  bad[1].changed_boxes = {{glm::vec3(1.0f), glm::vec3(0.0f)}}; // min > max
  bad[2].max_depth = 13;
  bad[3].split_low = -0.1f;
  bad[4].split_low = 0.6f, bad[4].split_high = 0.5f;
  bad[5].dead_backface_fraction = nan;
  bad[6].limits.max_light_entries = -1;
  for (std::size_t i = 0; i < bad.size(); ++i) {
    auto stats = gpu.value().run_frame(bad[i]);
    ASSERT_FALSE(stats.ok()) << "input " << i;
    EXPECT_EQ(stats.status().code, runtime::StatusCode::invalid_argument) << "input " << i;
    EXPECT_NE(stats.status().message.find("run_frame"), std::string::npos) << stats.status().message;
  }
  auto fine = gpu.value().run_frame({});
  ASSERT_TRUE(fine.ok()) << fine.status().message;
  EXPECT_TRUE(gpu.value().validate_live().ok());
  // A volume without the memory update refuses what only the memory update could act on.
  auto fixed = runtime::Volume::upload(context(), shallow_cornell());
  ASSERT_TRUE(fixed.ok()) << fixed.status().message;
  runtime::FrameInputs boxes;
  boxes.changed_boxes = {root_box(shallow_cornell())};
  auto refused = fixed.value().run_frame(boxes);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code, runtime::StatusCode::invalid_argument);
  EXPECT_NE(refused.status().message.find("memory update"), std::string::npos) << refused.status().message;
  runtime::FrameInputs limited;
  limited.limits = {2, 2};
  EXPECT_TRUE(fixed.value().run_frame(limited).ok()); // limits alone are harmless
}

} // namespace
} // namespace probebake::test
