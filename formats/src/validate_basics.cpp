// Validator phases that need no traversal: VolumeInfo settings (grid resolution, cell depth), counts
// against buffer sizes, buffers that need another one, finiteness of every float, and the leaf buffer of
// the octree thesis §3.1.4.
#include <cmath>
#include <unordered_set>

#include "probebake/formats/cells.h"
#include "probebake/formats/placement_kind.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

constexpr int kMaxSvoDepth = 30;

bool probe_finite(const gpu::Probe& probe) {
  if (!finite3(probe.position) || !all_finite({probe.hit_fraction, probe.backface_fraction, probe.pad0})) return false;
  for (float coefficient : probe.irradiance_sh) {
    if (!std::isfinite(coefficient)) return false;
  }
  return true;
}

long long allocated_probes(const ProbeVolume& volume) {
  long long allocated = 0;
  for (const gpu::Probe& probe : volume.probes) allocated += probe.link != 0;
  return allocated;
}

// Grid placement puts at most N^3 probes (dead ones are freed); N is bounded like the bake's --grid.
void check_grid_resolution(const ProbeVolume& volume, Reporter& out) {
  const gpu::VolumeInfo& info = volume.info;
  auto bad = [&](const std::string& message) { out.add("grid_resolution", "volume_info", 0, message); };
  const PlacementKindInfo* kind = placement_kind_for_code(info.placement);
  if (kind == nullptr || !kind->uses_grid_resolution) {
    const std::string_view name = kind != nullptr ? kind->name : "unknown";
    if (info.grid_resolution != 0)
      bad(concat("grid_resolution ", info.grid_resolution, " with ", name, " placement (must be 0)"));
    return;
  }
  if (info.grid_resolution < 1 || info.grid_resolution > kMaxGridResolution) {
    return bad(concat("grid_resolution ", info.grid_resolution, " outside [1, ", kMaxGridResolution, "]"));
  }
  const long long n = info.grid_resolution, allocated = allocated_probes(volume);
  if (allocated > n * n * n) bad(concat(allocated, " allocated probes, more than grid_resolution^3 = ", n * n * n));
}

// The header's cell depth describes the cells section: a file without cells has depth 0. Without any
// allocated probe arrange_cells writes no record, so the depth alone proves nothing then.
void check_cell_depth(const ProbeVolume& volume, Reporter& out) {
  if (volume.cell_depth < 0 || volume.cell_depth > kMaxCellDepth) {
    out.add("cell_depth", "cells", -1, concat("cell depth ", volume.cell_depth, " outside [0, ", kMaxCellDepth, "]"));
  } else if (volume.cell_depth != 0 && volume.cells.empty() && allocated_probes(volume) > 0) {
    out.add("cell_depth", "cells", -1,
            concat("cell depth ", volume.cell_depth, " but no cells section (a file without cells has depth 0)"));
  }
}

bool is_zero(const gpu::LeafQueueHeader& h) {
  return h.pull_origin == 0 && h.segment_capacity == 0 && h.count[0] == 0 && h.count[1] == 0 && h.count[2] == 0 &&
         h.pad0 == 0 && h.pad1 == 0 && h.pad2 == 0;
}

void check_count(Reporter& out, const char* section, long long expected, std::size_t actual, const char* what) {
  if (static_cast<long long>(actual) != expected) {
    out.add("count_mismatch", section, -1, concat(what, " is ", expected, " but the buffer has ", actual, " elements"));
  }
}

} // namespace

void check_volume_info(const ProbeVolume& volume, Reporter& out) {
  const gpu::VolumeInfo& info = volume.info;
  auto bad = [&](const std::string& message) { out.add("volume_info", "volume_info", 0, message); };
  if (std::isfinite(info.root_size) && !(info.root_size > 0.0f))
    bad(concat("root_size ", info.root_size, " is not positive"));
  if (placement_kind_for_code(info.placement) == nullptr) bad(concat("unknown placement ", info.placement));
  if (info.max_depth < 0 || info.max_depth > gpu::OCTREE_MAX_DEPTH)
    bad(concat("max_depth ", info.max_depth, " outside [0, OCTREE_MAX_DEPTH]"));
  if (info.svo_depth < 0 || info.svo_depth > kMaxSvoDepth)
    bad(concat("svo_depth ", info.svo_depth, " outside [0, ", kMaxSvoDepth, "]"));
  if (info.lattice < gpu::LATTICE_FIBONACCI || info.lattice > gpu::LATTICE_EQUAL_AREA)
    bad(concat("unknown lattice ", info.lattice));
  if (info.surfels_per_probe < 1 || info.surfels_per_probe > kMaxSurfelsPerProbe) {
    bad(concat("surfels_per_probe ", info.surfels_per_probe, " outside [1, ", kMaxSurfelsPerProbe, "]"));
  }
  if (all_finite({info.split_low, info.split_high}) &&
      !(info.split_low >= 0.0f && info.split_low <= info.split_high && info.split_high <= 1.0f)) {
    bad(concat("split thresholds ", info.split_low, ", ", info.split_high, " not 0 <= low <= high <= 1"));
  }
  if (info.pad0 != 0 || info.pad1 != 0 || info.pad2 != 0) bad("padding is not zero");
  check_grid_resolution(volume, out);
  check_cell_depth(volume, out);
}

void check_counts(const ProbeVolume& volume, Reporter& out) {
  const gpu::VolumeInfo& info = volume.info;
  check_count(out, "octree", info.octree_elements, volume.octree.size(), "octree_elements");
  check_count(out, "probes", info.probe_capacity, volume.probes.size(), "probe_capacity");
  check_count(out, "surfel_batches", info.batch_capacity, volume.surfel_batches.size(), "batch_capacity");
  check_count(out, "svo_nodes", info.svo_nodes, volume.svo_nodes.size(), "svo_nodes");
  check_count(out, "svo_leaves", info.svo_leaves, volume.svo_leaves.size(), "svo_leaves");
  check_count(out, "probe_index", static_cast<long long>(volume.probes.size()) + 1, volume.probe_index.size(),
              "probe capacity + 1");
  if (!volume.leaf_entries.empty() || volume.leaf_header.segment_capacity != 0) {
    check_count(out, "leaf_entries", 3LL * volume.leaf_header.segment_capacity, volume.leaf_entries.size(),
                "3 x segment_capacity");
  }
}

// Buffers that only make sense with another one (a missing section is an empty buffer). The lighting
// sections' dependency on lighting_info is checked with them (lighting_sections).
void check_dependencies(const ProbeVolume& volume, Reporter& out) {
  auto needs = [&](bool present, const char* section, bool dependency_present, const char* why) {
    if (present && !dependency_present) out.add("section_dependency", section, -1, why);
  };
  needs(!volume.surfel_batches.empty(), "surfel_batches", !volume.probes.empty(),
        "surfel batches without probes to own them");
  needs(!volume.svo_leaves.empty(), "svo_leaves", !volume.svo_nodes.empty(),
        "SVO leaf payloads without SVO nodes to reference them");
  needs(!is_zero(volume.leaf_header), "leaf_queue_header", !volume.leaf_entries.empty(),
        "a leaf queue header without leaf entries");
}

void check_finite(const ProbeVolume& volume, Reporter& out) {
  const gpu::VolumeInfo& info = volume.info;
  if (!finite3(info.root_min) || !all_finite({info.root_size, info.split_low, info.split_high})) {
    out.add("non_finite", "volume_info", 0, "a float is NaN or infinite");
  }
  for (std::size_t i = 0; i < volume.probes.size(); ++i) {
    if (!probe_finite(volume.probes[i]))
      out.add("non_finite", "probes", static_cast<long long>(i), "a float is NaN or infinite");
  }
  for (std::size_t b = 0; b < volume.surfel_batches.size(); ++b) {
    for (int s = 0; s < gpu::SURFELS_PER_BATCH; ++s) {
      if (!surfel_finite(volume.surfel_batches[b].surfels[s])) {
        out.add("non_finite", "surfel_batches", static_cast<long long>(b),
                concat("surfel ", s, " has a NaN or infinite float"));
        break;
      }
    }
  }
  for (std::size_t i = 0; i < volume.svo_leaves.size(); ++i) {
    const glm::vec4& w = volume.svo_leaves[i].weights;
    if (!all_finite({w.x, w.y, w.z, w.w}))
      out.add("non_finite", "svo_leaves", static_cast<long long>(i), "a weight is NaN or infinite");
  }
  for (std::size_t i = 0; i < volume.cells.size(); ++i) {
    if (!finite3(volume.cells[i].bounds_min) || !finite3(volume.cells[i].bounds_max)) {
      out.add("non_finite", "cells", static_cast<long long>(i), "bounds are NaN or infinite");
    }
  }
  check_lighting_finite(volume, out);
}

// §3.1.4: three segments used as a ring; entries in use hold (node, state) pairs, each node at most once
// per segment. Entries past a segment's count are scratch space and not checked.
void check_leaf_queue(const ProbeVolume& volume, const OctreeFacts& octree, Reporter& out) {
  if (volume.leaf_entries.empty()) return;
  const gpu::LeafQueueHeader& header = volume.leaf_header;
  const int capacity = header.segment_capacity;
  bool header_ok = true;
  auto bad_header = [&](const std::string& message) {
    header_ok = false;
    out.add("leaf_queue_header", "leaf_queue_header", 0, message);
  };
  if (header.pull_origin < 0 || header.pull_origin > 2)
    bad_header(concat("pull origin ", header.pull_origin, " not in {0, 1, 2}"));
  for (int s = 0; s < 3; ++s) {
    if (header.count[s] < 0 || header.count[s] > capacity)
      bad_header(concat("segment ", s, " count ", header.count[s], " outside [0, ", capacity, "]"));
  }
  if (header.pad0 != 0 || header.pad1 != 0 || header.pad2 != 0) bad_header("padding is not zero");
  if (!header_ok || volume.leaf_entries.size() != 3 * static_cast<std::size_t>(capacity)) return;

  for (int s = 0; s < 3; ++s) {
    std::unordered_set<int> seen;
    for (int e = 0; e < header.count[s]; ++e) {
      const long long index = static_cast<long long>(s) * capacity + e;
      const gpu::LeafEntry& entry = volume.leaf_entries[static_cast<std::size_t>(index)];
      // M0 and M4 address a parent (a child allocates; free the children); every other state a leaf.
      const bool parent_state =
          entry.state == gpu::LEAF_M0_CHILD_ALLOCATING || entry.state == gpu::LEAF_M4_FREE_CLUSTER;
      if (!octree.reachable(entry.node) || (volume.octree[entry.node] > 0) != parent_state) {
        out.add("leaf_entry_node", "leaf_entries", index,
                concat("node ", entry.node,
                       parent_state ? " is not a parent of the octree" : " is not a leaf of the octree"));
      }
      if (entry.state < 0 || entry.state >= gpu::LEAF_STATE_COUNT) {
        out.add("leaf_entry_state", "leaf_entries", index, concat("state ", entry.state, " is not a LEAF_* state"));
      }
      if (!seen.insert(entry.node).second) {
        out.add("leaf_entry_duplicate", "leaf_entries", index,
                concat("node ", entry.node, " appears twice in segment ", s));
      }
    }
  }
}

} // namespace probebake::formats::detail
