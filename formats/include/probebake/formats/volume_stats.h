// Summary numbers of a probe volume, for `probebake info` and the bake report.
#pragma once

#include <cstdint>
#include <vector>

#include "probebake/formats/probe_volume.h"
#include "probebake/formats/sh_codec.h"

namespace probebake::formats {

struct VolumeStats {
  int probes = 0; // allocated probes
  int nodes = 0;  // nodes reachable from the root (root included)
  int leaves = 0;
  int clusters = 0;                  // node clusters in the tree
  int max_depth = 0;                 // deepest leaf
  std::vector<int> probes_per_depth; // index = depth, size max_depth + 1
  int surfel_batches = 0;            // allocated batches
  long long surfels = 0;             // sum of the allocated batches' counts
  int svo_leaf_voxels = 0;           // SVO nodes that are leaves
};

// Throws Error(input) when the octree is not a tree (see for_each_leaf).
VolumeStats compute_stats(const ProbeVolume& volume);

// What a game keeps on the GPU to answer lookups (issue #41): volume_info, the probes and the lookup's index,
// without what the memory and light updates add (octree, surfels, leaf buffer, probe index list, tracing).
enum class LookupIndex {
  svo,          // probe_index::sample_irradiance: the SVO's nodes and leaves
  grid_lattice, // probe_index::sample_irradiance_grid: the lattice (0 bytes of index but its point words)
  none,         // the all-probe loop: no index (and the scene's rays, which are not counted)
};
// `codec` l2 or l1: the probes as the lookups then read them (runtime UploadOptions::probe_code), a point
// (16 bytes) and a code (32 or 16 bytes) per probe slot, instead of the 144-byte records.
std::uint64_t lookup_bytes(const ProbeVolume& volume, LookupIndex index, ShCodec codec = ShCodec::float32);

} // namespace probebake::formats
