// Streaming cells: arrange_cells makes each cell's probes, batches and SVO payloads contiguous with all
// links remapped, and a reader can take one cell's bytes straight out of the file.
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

using testing::Sample;

std::string first_violation(const ProbeVolume& volume) {
  const ValidationReport report = validate(volume);
  return report.violations.empty() ? "" : format_violation(report.violations.front());
}

TEST(Cells, SampleCellsCoverEveryAllocatedElement) {
  const ProbeVolume volume = testing::make_sample(Sample::small);
  ASSERT_GE(volume.cells.size(), 2u);
  std::uint32_t probes = 0, batches = 0, leaves = 0;
  for (const Cell& cell : volume.cells) {
    for (std::uint32_t i = 0; i < cell.probes.count; ++i) {
      EXPECT_EQ(cell_of_point(volume.info, 1, volume.probes[cell.probes.first + i].position), cell.cell_index);
    }
    probes += cell.probes.count, batches += cell.surfel_batches.count, leaves += cell.svo_leaves.count;
  }
  std::uint32_t allocated = 0, allocated_batches = 0;
  for (const gpu::Probe& p : volume.probes) allocated += p.link != 0;
  for (const gpu::SurfelBatch& b : volume.surfel_batches) allocated_batches += b.link != 0;
  EXPECT_EQ(probes, allocated);
  EXPECT_EQ(batches, allocated_batches);
  EXPECT_EQ(leaves, volume.svo_leaves.size() - 1); // one payload is unused
}

TEST(Cells, OneCellLoadsFromItsByteRanges) {
  const ProbeVolume volume = testing::make_sample(Sample::small);
  const std::vector<std::uint8_t> bytes = write_probes(volume);
  const ContainerView view = parse_container(bytes, "small");
  std::span<const std::uint8_t> probe_section;
  for (std::size_t i = 0; i < view.sections.size(); ++i) {
    if (view.sections[i].type == static_cast<std::uint32_t>(SectionType::probes)) probe_section = view.payloads[i];
  }
  const Cell& cell = volume.cells.back();
  ASSERT_GT(cell.probes.count, 0u);
  const std::span<const std::uint8_t> range = probe_section.subspan(cell.probes.byte_offset, cell.probes.byte_size);
  EXPECT_EQ(std::memcmp(range.data(), &volume.probes[cell.probes.first], range.size()), 0);
}

TEST(Cells, RootNodeIsMinusOneWhereTheTreeIsShallower) {
  ProbeVolume volume = testing::make_sample(Sample::small);
  arrange_cells(volume, 2);
  EXPECT_EQ(first_violation(volume), "");
  int minus_one = 0, nodes = 0;
  for (const Cell& cell : volume.cells) (cell.root_node < 0 ? minus_one : nodes)++;
  EXPECT_GT(minus_one, 0);
  EXPECT_GT(nodes, 0);
}

TEST(Cells, ArrangeIsIdempotentAndWorksAtEveryDepth) {
  for (Sample sample : testing::kAllSamples) {
    for (int depth = 0; depth <= kMaxCellDepth; ++depth) {
      ProbeVolume volume = testing::make_sample(sample);
      arrange_cells(volume, depth);
      EXPECT_EQ(first_violation(volume), "") << testing::golden_name(sample) << " depth " << depth;
      const std::vector<std::uint8_t> once = write_probes(volume);
      arrange_cells(volume, depth);
      EXPECT_EQ(write_probes(volume), once);
    }
  }
  ProbeVolume volume = testing::make_sample(Sample::small);
  EXPECT_THROW(arrange_cells(volume, kMaxCellDepth + 1), Error);
  clear_cells(volume);
  EXPECT_EQ(first_violation(volume), "");
}

TEST(Cells, RandomTreesStayValidWhenArranged) {
  std::mt19937 rng(99);
  gpu::VolumeInfo info{};
  info.root_min = glm::vec3(3.0f, -5.0f, 0.5f);
  info.root_size = 10.0f;
  info.max_depth = 4;
  info.surfels_per_probe = 2 * gpu::SURFELS_PER_BATCH; // batches below hold lattice points [0, 1)
  info.split_high = 1.0f;
  for (int trial = 0; trial < 20; ++trial) {
    ProbeVolume volume = make_empty_volume(info);
    Octree tree(volume);
    for (int step = 0; step < 200; ++step) {
      std::vector<int> leaves;
      for_each_leaf(volume, [&](const NodeCube& leaf) { leaves.push_back(leaf.node); });
      const int leaf = leaves[rng() % leaves.size()];
      if (rng() % 3 == 0) {
        tree.split(leaf);
      } else if (volume.octree[leaf] == 0) {
        const int probe = tree.place_probe(leaf);
        for (auto b = rng() % 3; b > 0; --b) volume.surfel_batches[tree.append_surfel_batch(probe)].count = 1;
      } else {
        tree.free_probe(tree.probe_of(leaf));
      }
    }
    rebuild_probe_index(volume);
    ASSERT_EQ(first_violation(volume), "");
    arrange_cells(volume, static_cast<int>(rng() % 4));
    ASSERT_EQ(first_violation(volume), "") << "trial " << trial;
  }
}

} // namespace
} // namespace probebake::formats
