// The probe octree on the thesis's buffer layout (octree thesis §3.1.1 octree buffer, §3.1.2 probes,
// §3.1.3 surfel batches, §3.1.5 probe index list), operating in place on a ProbeVolume.
//
// Layout reminder (gpu_types.h): octree[0] is the root node; then clusters of nine int32: a meta element
// (0 = free, < 0 = ~parent node) followed by eight sibling nodes (0 = leaf, < 0 = leaf with probe ~value,
// > 0 = parent whose children are the cluster at meta index value). Child `octant` of a cube covers the
// half-cube selected by bit 0 (+x), bit 1 (+y), bit 2 (+z), as in the SVO.
//
// Unlike the thesis (linear scans for a free element), allocation pops free lists: O(1). The free lists
// are side data, not stored in the buffers (free elements stay all-zero, as the validator requires), so
// they can always be rebuilt by one scan of the buffers (rebuild_free_lists).
//
// Thread-safety: none; an Octree is the only writer of its volume's octree, probes, surfel batches and
// counts while it is alive. Coordinates are world space, metres.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/probe_volume.h"

namespace probebake::formats {

inline constexpr int kNoIndex = -1;

// ---- Index arithmetic of the octree buffer ------------------------------------------------------------
// Meta index of the cluster holding node `node` (node must be in N, i.e. not the root).
constexpr int cluster_meta_of(int node) { return 1 + ((node - 1) / 9) * 9; }
// Octant (0..7) of a non-root node inside its cluster.
constexpr int octant_of(int node) { return node - cluster_meta_of(node) - 1; }
// Node index of child `octant` of the cluster at meta index `meta`.
constexpr int child_node(int meta, int octant) { return meta + 1 + octant; }
constexpr bool is_meta_index(int index) { return index >= 1 && (index - 1) % 9 == 0; }
// True for the root and the eight node slots of every cluster (the set R u N of §3.1.1).
constexpr bool is_node_index(int index) { return index == 0 || (index >= 1 && (index - 1) % 9 != 0); }
// Complete clusters in an octree buffer of `elements` int32 (a trailing incomplete cluster excluded).
constexpr std::size_t complete_clusters(std::size_t elements) { return elements == 0 ? 0 : (elements - 1) / 9; }

// ---- Geometry -------------------------------------------------------------------------------------------
// The cube of one octree node.
struct NodeCube {
  int node = 0;        // octree buffer index
  int depth = 0;       // root = 0
  glm::vec3 min{0.0f}; // minimum corner, world space
  float size = 0.0f;   // edge length
  glm::vec3 centre() const { return min + glm::vec3(0.5f * size); }
};

NodeCube root_cube(const gpu::VolumeInfo& info);
// Cube of child `octant` of `parent`; `.node` is left to the caller.
NodeCube child_cube(const NodeCube& parent, int octant);

// Cube of any reachable node, found by climbing meta -> parent links to the root, then descending.
// Throws Error(input) when the links are broken (out of range, cycle, deeper than OCTREE_MAX_DEPTH).
NodeCube node_cube(const ProbeVolume& volume, int node);

// Calls `visit` for every leaf in depth-first order (children in octant order). Throws Error(input) if
// the octree is not a tree (a child index out of range or a cluster reached twice) or is deeper than
// OCTREE_MAX_DEPTH; it never loops. Visiting is O(nodes).
void for_each_leaf(const ProbeVolume& volume, const std::function<void(const NodeCube&)>& visit);

// The leaf whose cube contains `point` (cubes are half-open [min, min + size), except that the root's
// maximum faces belong to it too); nullopt outside the root cube or for a non-finite point.
std::optional<NodeCube> find_leaf(const ProbeVolume& volume, glm::vec3 point);

// Rewrites volume.probe_index (§3.1.5): the allocated probes (link != 0) in ascending order, then
// PROBE_INDEX_END up to probe_capacity + 1 elements.
void rebuild_probe_index(ProbeVolume& volume);

// ---- Mutation ---------------------------------------------------------------------------------------------
// Allocates and frees node clusters, probes and surfel batches of one volume; keeps the links of both
// ends and the counts in volume.info consistent. Preconditions that are caller bugs (an index that is
// not a leaf, a free probe) throw Error(internal). Running out of space returns kNoIndex in
// Growth::fixed mode (the GPU runtime's fixed buffers, for the CPU reference); Growth::automatic grows
// the buffers (amortised doubling).
class Octree {
public:
  enum class Growth { automatic, fixed };

  // Takes the volume as it is (it must be valid, e.g. a fresh make_empty_volume or a validated file) and
  // builds the free lists from its buffers. `volume` must outlive the Octree.
  explicit Octree(ProbeVolume& volume, Growth growth = Growth::automatic);

  // Scans the buffers again; needed only after the volume was modified by someone else.
  void rebuild_free_lists();

  ProbeVolume& volume() { return *volume_; }
  const ProbeVolume& volume() const { return *volume_; }

  // -- Nodes. A node with value 0 is a leaf, < 0 a leaf with probe, > 0 a parent.
  bool is_leaf(int node) const { return volume_->octree[node] <= 0; }
  // Probe of a leaf, kNoIndex when the node has none.
  int probe_of(int node) const { return volume_->octree[node] < 0 ? ~volume_->octree[node] : kNoIndex; }

  // Makes leaf `leaf` a parent of eight new probe-less leaves. A probe in `leaf` is freed first (with its
  // surfels): parents hold no probe. Returns the meta index of the new cluster, or kNoIndex when the
  // leaf is at info.max_depth or (Growth::fixed) no complete cluster is free.
  int split(int leaf);

  // Frees the child cluster of parent `node` and makes `node` a probe-less leaf, only when all eight
  // children are leaves without probes; returns whether it did.
  bool collapse(int node);

  // -- Probes
  // Allocates a probe for leaf `leaf` (which must not hold one) at the centre of its cube, with the
  // node's depth, link = ~PROBE_NO_SURFELS, zero irradiance. Returns the probe index or kNoIndex.
  int place_probe(int leaf);
  // Detaches probe `probe` from its leaf (grid probes have none), frees its surfel chain and zeroes it.
  void free_probe(int probe);

  // -- Surfel batches (§3.1.3): a probe's chain ends in a batch whose link is owner + 1.
  // Appends a zeroed batch (count 0, caller fills count/first/surfels) to the probe's chain and
  // returns its index, or kNoIndex.
  int append_surfel_batch(int probe);
  // Frees all batches of the probe's chain; the probe keeps link = ~PROBE_NO_SURFELS.
  void free_surfel_chain(int probe);

  // -- Capacity: grow the buffers so that at least `count` more elements can be allocated without
  // growth (always allowed, also in Growth::fixed mode).
  void reserve_clusters(int count);
  void reserve_probes(int count);
  void reserve_batches(int count);
  int free_clusters() const { return static_cast<int>(free_clusters_.size()); }
  int free_probes() const { return static_cast<int>(free_probes_.size()); }
  int free_batches() const { return static_cast<int>(free_batches_.size()); }

private:
  int allocate_cluster(int parent);
  void release_cluster(int meta);
  int allocate_probe();
  int allocate_batch();
  void release_batch(int batch);
  int take_free(std::vector<int>& list, void (Octree::*grow)(int), std::size_t capacity);
  void grow_clusters(int count);
  void grow_probes(int count);
  void grow_batches(int count);
  void check_node(int node, const char* what) const;
  void check_allocated_probe(int probe, const char* what) const;

  ProbeVolume* volume_;
  Growth growth_;
  // Stacks: back() is allocated next; rebuilt in descending order so that fresh buffers fill from the
  // lowest index, and a freed element is the next one reused.
  std::vector<int> free_clusters_;
  std::vector<int> free_probes_;
  std::vector<int> free_batches_;
};

} // namespace probebake::formats
