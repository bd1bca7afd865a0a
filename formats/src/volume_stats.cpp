// Summary numbers of a volume (probe count, depth histogram, ...), for `probebake info` and bake reports.
#include "probebake/formats/volume_stats.h"

#include <algorithm>

#include "probebake/formats/octree.h"

namespace probebake::formats {

std::uint64_t lookup_bytes(const ProbeVolume& volume, LookupIndex index, ShCodec codec) {
  const std::uint64_t probe_bytes =
      codec == ShCodec::float32 ? sizeof(gpu::Probe) : sizeof(glm::vec4) + std::uint64_t(sh_codec_bytes(codec));
  std::uint64_t bytes = sizeof(gpu::VolumeInfo) + volume.probes.size() * probe_bytes;
  if (index == LookupIndex::svo)
    bytes += volume.svo_nodes.size() * sizeof(std::int32_t) + volume.svo_leaves.size() * sizeof(gpu::SvoLeaf);
  if (index == LookupIndex::grid_lattice) bytes += volume.grid_lattice.size() * sizeof(std::uint32_t);
  return bytes;
}

VolumeStats compute_stats(const ProbeVolume& volume) {
  VolumeStats stats;
  for_each_leaf(volume, [&](const NodeCube& leaf) {
    ++stats.leaves;
    stats.max_depth = std::max(stats.max_depth, leaf.depth);
  });
  // A full octree with L leaves has (L - 1) / 7 parents, one cluster each.
  stats.clusters = (stats.leaves - 1) / 7;
  stats.nodes = stats.leaves + stats.clusters;
  stats.probes_per_depth.assign(static_cast<std::size_t>(stats.max_depth) + 1, 0);
  for (const gpu::Probe& probe : volume.probes) {
    if (probe.link == 0) continue;
    ++stats.probes;
    // Depths are untrusted here (info runs on unvalidated files): only in-range ones are counted.
    if (probe.depth >= 0 && probe.depth <= stats.max_depth)
      ++stats.probes_per_depth[static_cast<std::size_t>(probe.depth)];
  }
  for (const gpu::SurfelBatch& batch : volume.surfel_batches) {
    if (batch.link == 0) continue;
    ++stats.surfel_batches;
    stats.surfels += batch.count;
  }
  stats.svo_leaf_voxels =
      static_cast<int>(std::count_if(volume.svo_nodes.begin(), volume.svo_nodes.end(), [](int n) { return n < 0; }));
  return stats;
}

} // namespace probebake::formats
