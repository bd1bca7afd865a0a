// Octree mutation on the buffer layout of the octree thesis §3.1.1-3.1.3: node clusters, probes and
// surfel batches are taken from free lists (O(1)) instead of the thesis's linear scans of the buffers.
// The free lists live beside the buffers; free elements in the buffers stay all-zero.
#include <algorithm>
#include <limits>
#include <string>

#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"

namespace probebake::formats {
namespace {

constexpr int kMinGrowth = 8;
constexpr std::size_t kMaxElements = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());

[[noreturn]] void throw_misuse(const std::string& what) { throw Error(ErrorKind::internal, "octree: " + what); }

// Puts freshly created element indices [first, last) under the existing free entries, highest first, so
// that the stack keeps handing out low indices first.
void add_fresh(std::vector<int>& free_list, int first, int last, int step) {
  std::vector<int> fresh;
  for (int index = last - step; index >= first; index -= step) fresh.push_back(index);
  free_list.insert(free_list.begin(), fresh.begin(), fresh.end());
}

int grown_size(std::size_t current, int count, std::size_t element_units, const char* what) {
  const std::size_t wanted = current + static_cast<std::size_t>(count) * element_units;
  if (count < 0 || wanted > kMaxElements)
    throw Error(ErrorKind::internal, std::string(what) + ": capacity exceeds INT32_MAX");
  return static_cast<int>(wanted);
}

} // namespace

Octree::Octree(ProbeVolume& volume, Growth growth) : volume_(&volume), growth_(growth) {
  if (volume.octree.empty()) throw_misuse("volume has no root node (use make_empty_volume)");
  rebuild_free_lists();
}

void Octree::rebuild_free_lists() {
  const ProbeVolume& v = *volume_;
  free_clusters_.clear();
  for (std::size_t cluster = complete_clusters(v.octree.size()); cluster-- > 0;) {
    const int meta = static_cast<int>(1 + 9 * cluster);
    if (v.octree[meta] == 0) free_clusters_.push_back(meta);
  }
  free_probes_.clear();
  for (std::size_t probe = v.probes.size(); probe-- > 0;) {
    if (v.probes[probe].link == 0) free_probes_.push_back(static_cast<int>(probe));
  }
  free_batches_.clear();
  for (std::size_t batch = v.surfel_batches.size(); batch-- > 0;) {
    if (v.surfel_batches[batch].link == 0) free_batches_.push_back(static_cast<int>(batch));
  }
}

// ---- Nodes ------------------------------------------------------------------------------------------------

void Octree::check_node(int node, const char* what) const {
  const std::size_t usable = 1 + 9 * complete_clusters(volume_->octree.size());
  if (node < 0 || static_cast<std::size_t>(node) >= usable || !is_node_index(node)) {
    throw_misuse(std::string(what) + ": " + std::to_string(node) + " is not a node index");
  }
}

int Octree::split(int leaf) {
  check_node(leaf, "split");
  if (!is_leaf(leaf)) throw_misuse("split: node " + std::to_string(leaf) + " is not a leaf");
  if (node_cube(*volume_, leaf).depth >= volume_->info.max_depth) return kNoIndex;
  const int meta = allocate_cluster(leaf);
  if (meta == kNoIndex) return kNoIndex;
  if (const int probe = probe_of(leaf); probe != kNoIndex) free_probe(probe);
  volume_->octree[leaf] = meta;
  return meta;
}

bool Octree::collapse(int node) {
  check_node(node, "collapse");
  const int meta = volume_->octree[node];
  if (meta <= 0) throw_misuse("collapse: node " + std::to_string(node) + " is not a parent");
  for (int octant = 0; octant < 8; ++octant) {
    if (volume_->octree[child_node(meta, octant)] != 0) return false;
  }
  release_cluster(meta);
  volume_->octree[node] = 0;
  return true;
}

int Octree::allocate_cluster(int parent) {
  const int meta = take_free(free_clusters_, &Octree::grow_clusters, complete_clusters(volume_->octree.size()));
  if (meta == kNoIndex) return kNoIndex;
  volume_->octree[meta] = ~parent; // its eight nodes are already zero: leaves without probes
  return meta;
}

void Octree::release_cluster(int meta) {
  std::fill_n(volume_->octree.begin() + meta, gpu::OCTREE_CLUSTER_SIZE, 0);
  free_clusters_.push_back(meta);
}

// ---- Probes -----------------------------------------------------------------------------------------------

void Octree::check_allocated_probe(int probe, const char* what) const {
  if (probe < 0 || static_cast<std::size_t>(probe) >= volume_->probes.size() || volume_->probes[probe].link == 0) {
    throw_misuse(std::string(what) + ": probe " + std::to_string(probe) + " is not allocated");
  }
}

int Octree::place_probe(int leaf) {
  check_node(leaf, "place_probe");
  if (volume_->octree[leaf] != 0) throw_misuse("place_probe: node " + std::to_string(leaf) + " is not an empty leaf");
  const NodeCube cube = node_cube(*volume_, leaf);
  const int index = allocate_probe();
  if (index == kNoIndex) return kNoIndex;
  gpu::Probe& probe = volume_->probes[index];
  probe = gpu::Probe{};
  probe.position = cube.centre();
  probe.link = ~gpu::PROBE_NO_SURFELS;
  probe.node = leaf;
  probe.depth = cube.depth;
  volume_->octree[leaf] = ~index;
  return index;
}

int Octree::allocate_probe() { return take_free(free_probes_, &Octree::grow_probes, volume_->probes.size()); }

void Octree::free_probe(int probe) {
  check_allocated_probe(probe, "free_probe");
  free_surfel_chain(probe);
  const int node = volume_->probes[probe].node;
  if (node >= 0) { // grid probes (node -1) have no leaf
    check_node(node, "free_probe");
    if (volume_->octree[node] != ~probe)
      throw_misuse("free_probe: node " + std::to_string(node) + " does not link back");
    volume_->octree[node] = 0;
  }
  volume_->probes[probe] = gpu::Probe{};
  free_probes_.push_back(probe);
}

// ---- Surfel batches ---------------------------------------------------------------------------------------

int Octree::append_surfel_batch(int probe) {
  check_allocated_probe(probe, "append_surfel_batch");
  const int batch = allocate_batch();
  if (batch == kNoIndex) return kNoIndex;
  std::vector<gpu::SurfelBatch>& batches = volume_->surfel_batches;
  batches[batch] = gpu::SurfelBatch{};
  batches[batch].link = probe + 1; // last of the chain: owner + 1
  batches[batch].probe = probe;
  int& first_link = volume_->probes[probe].link;
  if (~first_link == gpu::PROBE_NO_SURFELS) {
    first_link = ~batch;
    return batch;
  }
  int last = ~first_link;
  for (std::size_t steps = 0; batches[last].link < 0; ++steps) {
    if (steps > batches.size()) throw_misuse("append_surfel_batch: endless chain");
    last = ~batches[last].link;
  }
  batches[last].link = ~batch;
  return batch;
}

void Octree::free_surfel_chain(int probe) {
  check_allocated_probe(probe, "free_surfel_chain");
  int& first_link = volume_->probes[probe].link;
  if (~first_link == gpu::PROBE_NO_SURFELS) return;
  int batch = ~first_link;
  for (std::size_t steps = 0;; ++steps) {
    if (steps > volume_->surfel_batches.size() || batch < 0 ||
        static_cast<std::size_t>(batch) >= volume_->surfel_batches.size()) {
      throw_misuse("free_surfel_chain: broken chain");
    }
    const int link = volume_->surfel_batches[batch].link;
    release_batch(batch);
    if (link >= 0) break;
    batch = ~link;
  }
  first_link = ~gpu::PROBE_NO_SURFELS;
}

int Octree::allocate_batch() { return take_free(free_batches_, &Octree::grow_batches, volume_->surfel_batches.size()); }

void Octree::release_batch(int batch) {
  volume_->surfel_batches[batch] = gpu::SurfelBatch{};
  free_batches_.push_back(batch);
}

// ---- Growth -----------------------------------------------------------------------------------------------

// Takes the last free slot of `list`. An empty list grows first, by amortised doubling (the current capacity,
// at least kMinGrowth), unless the growth is fixed: then there is no slot (kNoIndex).
int Octree::take_free(std::vector<int>& list, void (Octree::*grow)(int), std::size_t capacity) {
  if (list.empty()) {
    if (growth_ == Growth::fixed) return kNoIndex;
    (this->*grow)(static_cast<int>(std::clamp<std::size_t>(capacity, kMinGrowth, kMaxElements / 16)));
  }
  const int slot = list.back();
  list.pop_back();
  return slot;
}

// Grows by whole clusters. A trailing incomplete cluster (possible in a buffer from elsewhere) is never
// in use, so it is zeroed and completed first; the buffer then always ends on a cluster boundary.
void Octree::grow_clusters(int count) {
  std::vector<std::int32_t>& octree = volume_->octree;
  const std::size_t complete = complete_clusters(octree.size());
  const std::size_t boundary = 1 + 9 * complete;
  std::fill(octree.begin() + static_cast<std::ptrdiff_t>(boundary), octree.end(), 0);
  const int new_size = grown_size(boundary, count, 9, "octree");
  octree.resize(static_cast<std::size_t>(new_size), 0);
  add_fresh(free_clusters_, static_cast<int>(boundary), new_size, 9);
  volume_->info.octree_elements = new_size;
}

void Octree::grow_probes(int count) {
  const int old_size = static_cast<int>(volume_->probes.size());
  const int new_size = grown_size(volume_->probes.size(), count, 1, "probes");
  volume_->probes.resize(static_cast<std::size_t>(new_size), gpu::Probe{});
  // Keep the probe index list at capacity + 1 elements; its contents are refreshed by rebuild_probe_index.
  volume_->probe_index.resize(static_cast<std::size_t>(new_size) + 1, gpu::PROBE_INDEX_END);
  add_fresh(free_probes_, old_size, new_size, 1);
  volume_->info.probe_capacity = new_size;
}

void Octree::grow_batches(int count) {
  const int old_size = static_cast<int>(volume_->surfel_batches.size());
  const int new_size = grown_size(volume_->surfel_batches.size(), count, 1, "surfel_batches");
  volume_->surfel_batches.resize(static_cast<std::size_t>(new_size), gpu::SurfelBatch{});
  add_fresh(free_batches_, old_size, new_size, 1);
  volume_->info.batch_capacity = new_size;
}

void Octree::reserve_clusters(int count) {
  if (count > free_clusters()) grow_clusters(count - free_clusters());
}
void Octree::reserve_probes(int count) {
  if (count > free_probes()) grow_probes(count - free_probes());
}
void Octree::reserve_batches(int count) {
  if (count > free_batches()) grow_batches(count - free_batches());
}

} // namespace probebake::formats
