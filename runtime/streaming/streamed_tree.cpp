#include "streaming/streamed_tree.h"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "core/error.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/octree.h"

namespace probebake::runtime::detail {
namespace {

// A file subtree: its clusters and probes, the probes' irradiance summed.
struct Subtree {
  std::uint64_t clusters = 0;
  std::vector<int> probes;
  std::array<double, gpu::PROBE_SH_FLOATS> sum{};
};

// A tree that names a node twice (an unvalidated upload) would loop: no walk visits more nodes than it has.
void check_visits(std::size_t visited, const formats::ProbeVolume& file) {
  if (visited > file.octree.size())
    fail(StatusCode::invalid_argument, "octree: a node is reached twice (upload without validation?)");
}

// The subtree below `root`, walked with a stack.
Subtree tally(const formats::ProbeVolume& file, int root) {
  Subtree t;
  std::vector<int> stack{root};
  for (std::size_t visited = 0; !stack.empty(); check_visits(++visited, file)) {
    const int node = stack.back();
    stack.pop_back();
    const int v = file.octree.at(std::size_t(node)); // checked: an unvalidated upload may name any node
    if (v > 0) {
      ++t.clusters;
      for (int o = 0; o < 8; ++o) stack.push_back(formats::child_node(v, o));
    } else if (v < 0) {
      t.probes.push_back(~v);
      for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k)
        t.sum[std::size_t(k)] += file.probes.at(std::size_t(~v)).irradiance_sh[k];
    }
  }
  return t;
}

int place_probe(formats::Octree& tree, int leaf) {
  const int probe = tree.place_probe(leaf);
  if (probe < 0) fail(StatusCode::internal, "collapse_cells: no probe for node " + std::to_string(leaf));
  return probe;
}

// File probe `from` as the probe of `leaf`, with a copy of its surfel chain.
int copy_probe(const formats::ProbeVolume& file, int from, formats::Octree& tree, int leaf) {
  const int probe = place_probe(tree, leaf);
  const gpu::Probe& in = file.probes.at(std::size_t(from));
  gpu::Probe& out = tree.volume().probes[std::size_t(probe)];
  out.position = in.position;
  out.hit_fraction = in.hit_fraction;
  out.backface_fraction = in.backface_fraction;
  std::copy(std::begin(in.irradiance_sh), std::end(in.irradiance_sh), std::begin(out.irradiance_sh));
  int link = in.link;
  for (std::size_t steps = 0; ~link != gpu::PROBE_NO_SURFELS && link < 0; ++steps) {
    if (steps > file.surfel_batches.size()) fail(StatusCode::internal, "collapse_cells: endless surfel chain");
    const gpu::SurfelBatch& src = file.surfel_batches.at(std::size_t(~link));
    const int batch = tree.append_surfel_batch(probe);
    if (batch < 0) fail(StatusCode::internal, "collapse_cells: no surfel batch");
    gpu::SurfelBatch& dst = tree.volume().surfel_batches[std::size_t(batch)];
    dst.count = src.count;
    dst.first = src.first;
    std::copy(std::begin(src.surfels), std::end(src.surfels), std::begin(dst.surfels));
    link = src.link; // < 0: the next batch; > 0: the end (owner + 1)
  }
  return probe;
}

// A stencil's probes through `map` (file -> collapsed), a probe named twice keeping the sum of its weights.
gpu::SvoLeaf remap_stencil(const gpu::SvoLeaf& in, const std::vector<int>& map) {
  gpu::SvoLeaf out{glm::ivec4(-1), glm::vec4(0.0f)};
  int used = 0;
  float total = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const int p = in.probes[k];
    if (p < 0 || std::size_t(p) >= map.size() || map[std::size_t(p)] < 0) continue;
    int j = 0;
    while (j < used && out.probes[j] != map[std::size_t(p)]) ++j;
    if (j == used) out.probes[used++] = map[std::size_t(p)];
    out.weights[j] += in.weights[k];
    total += in.weights[k];
  }
  if (total > 0.0f) out.weights /= total;
  return out;
}

} // namespace

formats::ProbeVolume collapse_cells(const formats::ProbeVolume& file) {
  formats::ProbeVolume out = file;
  out.octree.assign(1, 0);
  out.probes.clear();
  out.surfel_batches.clear();
  out.leaf_entries.clear();
  out.leaf_header = gpu::LeafQueueHeader{};
  out.probe_index.assign(1, gpu::PROBE_INDEX_END);
  formats::sync_info_counts(out);
  formats::Octree tree(out, formats::Octree::Growth::automatic);
  std::vector<int> probe_map(file.probes.size(), -1); // file probe -> the probe standing for it
  struct Pending {
    int from, to, depth;
  };
  std::vector<Pending> queue{{gpu::OCTREE_ROOT, gpu::OCTREE_ROOT, 0}};
  for (std::size_t i = 0; i < queue.size(); check_visits(++i, file)) {
    const Pending n = queue[i];
    const int v = file.octree.at(std::size_t(n.from));
    if (v < 0) probe_map[std::size_t(~v)] = copy_probe(file, ~v, tree, n.to);
    if (v <= 0) continue;
    if (n.depth < file.cell_depth) {
      const int meta = tree.split(n.to);
      if (meta < 0) fail(StatusCode::internal, "collapse_cells: no cluster for node " + std::to_string(n.to));
      for (int o = 0; o < 8; ++o)
        queue.push_back({formats::child_node(v, o), formats::child_node(meta, o), n.depth + 1});
      continue;
    }
    const Subtree subtree = tally(file, n.from); // a cell's node with a subtree: one probe stands for it
    if (subtree.probes.empty()) continue;
    const int probe = place_probe(tree, n.to);
    for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k)
      out.probes[std::size_t(probe)].irradiance_sh[k] =
          float(subtree.sum[std::size_t(k)] / double(subtree.probes.size()));
    for (int p : subtree.probes) probe_map[std::size_t(p)] = probe;
  }
  for (gpu::SvoLeaf& leaf : out.svo_leaves) leaf = remap_stencil(leaf, probe_map);
  formats::sync_info_counts(out);
  return out;
}

SeatRoom resident_seat_room(const formats::ProbeVolume& file, std::span<const streaming::CellFootprint> footprints,
                            std::uint64_t budget) {
  std::vector<std::uint64_t> probes(footprints.size(), 0), clusters(footprints.size(), 0);
  for (std::size_t k = 0; k < footprints.size(); ++k) {
    const int root = formats::cell_root_node(file, file.cell_depth, footprints[k].cell_index);
    if (root < 0 || file.octree[std::size_t(root)] <= 0) continue; // nothing of its own to seat
    const Subtree subtree = tally(file, root);
    probes[k] = subtree.probes.size();
    clusters[k] = subtree.clusters;
  }
  return {streaming::most_resident(footprints, probes, budget), streaming::most_resident(footprints, clusters, budget)};
}

} // namespace probebake::runtime::detail
