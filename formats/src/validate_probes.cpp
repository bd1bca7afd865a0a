// Validator phases for probes (octree thesis §3.1.2), surfel batches (§3.1.3) and the probe index list
// (§3.1.5): probe <-> leaf links one-to-one, probe inside its node's cube at the node's depth, surfel
// chains finite, unshared and owned, free elements zeroed, the index list equal to the allocated probes;
// the values in probes and surfels (fractions, lattice ranges, flags, padding) in range.
#include <bit>
#include <cmath>
#include <cstring>
#include <initializer_list>

#include <glm/geometric.hpp>

#include "probebake/formats/placement_kind.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

bool inside(const gpu::Probe& probe, const NodeCube& cube, float relative_epsilon) {
  const float epsilon = relative_epsilon * cube.size;
  for (int axis = 0; axis < 3; ++axis) {
    const float p = probe.position[axis];
    if (!(p >= cube.min[axis] - epsilon && p <= cube.min[axis] + cube.size + epsilon)) return false;
  }
  return true;
}

bool finite_position(const gpu::Probe& probe) {
  return std::isfinite(probe.position.x) && std::isfinite(probe.position.y) && std::isfinite(probe.position.z);
}

// For every probe, the reachable leaf that links it (-1: none); links from leaves to missing or free
// probes and second links are reported here.
std::vector<int> leaf_links(const ProbeVolume& volume, const OctreeFacts& octree, std::vector<bool>& reported,
                            Reporter& out) {
  const std::size_t probe_count = volume.probes.size();
  std::vector<int> linked_from(probe_count, -1);
  for (std::size_t node = 0; node < volume.octree.size(); ++node) {
    const int value = volume.octree[node];
    if (value >= 0 || !octree.reachable(static_cast<int>(node))) continue;
    const int probe = ~value;
    if (static_cast<std::size_t>(probe) >= probe_count) {
      out.add("probe_leaf_link", "octree", static_cast<long long>(node),
              concat("links probe ", probe, ", out of range"));
    } else if (volume.probes[probe].link == 0) {
      out.add("probe_leaf_link", "octree", static_cast<long long>(node),
              concat("links probe ", probe, ", which is free"));
    } else if (linked_from[probe] >= 0) {
      reported[probe] = true;
      out.add("probe_leaf_link", "probes", probe,
              concat("linked from two leaves, ", linked_from[probe], " and ", node));
    } else {
      linked_from[probe] = static_cast<int>(node);
    }
  }
  return linked_from;
}

bool fraction(float value) { return value >= 0.0f && value <= 1.0f; }

// Fractions are counts over counts, so they lie in [0, 1] for free probes (zero) too. Non-finite values
// are non_finite's.
void check_probe_values(const ProbeVolume& volume, Reporter& out) {
  for (std::size_t i = 0; i < volume.probes.size(); ++i) {
    const gpu::Probe& probe = volume.probes[i];
    if (!all_finite({probe.hit_fraction, probe.backface_fraction, probe.pad0})) continue;
    const long long index = static_cast<long long>(i);
    if (!fraction(probe.hit_fraction) || !fraction(probe.backface_fraction)) {
      out.add("probe_values", "probes", index,
              concat("fractions ", probe.hit_fraction, ", ", probe.backface_fraction, " not in [0, 1]"));
    } else if (!zero_bits({probe.pad0})) {
      out.add("probe_values", "probes", index, "padding is not zero");
    }
  }
}

std::string surfel_problem(const gpu::Surfel& s) {
  if ((s.flags & ~(gpu::SURFEL_FLAG_HIT | gpu::SURFEL_FLAG_BACKFACE)) != 0)
    return concat("unknown flag bits ", s.flags);
  const bool hit = (s.flags & gpu::SURFEL_FLAG_HIT) != 0;
  if (!hit && (s.flags & gpu::SURFEL_FLAG_BACKFACE) != 0) return "back-face flag without the hit flag";
  if (s.distance < 0.0f) return concat("distance ", s.distance, " is negative");
  if (hit && !unit(s.normal)) return "a hit's normal is not a unit vector";
  if (negative(s.albedo) || negative(s.radiance)) return "negative albedo or radiance";
  if (!zero_bits({s.pad0, s.pad1})) return "padding is not zero";
  return "";
}

// Surfels in use hold sane values; the ones past `count` were never written and stay zero. One
// violation per batch is enough to find it.
void check_surfels(const gpu::SurfelBatch& batch, long long index, Reporter& out) {
  static const gpu::Surfel kZero{};
  for (int k = 0; k < gpu::SURFELS_PER_BATCH; ++k) {
    const gpu::Surfel& surfel = batch.surfels[k];
    std::string problem;
    if (k >= batch.count) {
      if (std::memcmp(&surfel, &kZero, sizeof(gpu::Surfel)) != 0)
        problem = concat("surfel ", k, " is past count ", batch.count, " but not zero");
    } else if (surfel_finite(surfel)) {
      if (const std::string what = surfel_problem(surfel); !what.empty()) problem = concat("surfel ", k, ": ", what);
    }
    if (!problem.empty()) return out.add("surfel_values", "surfel_batches", index, problem);
  }
}

// The batch's surfels are lattice points [first, first + count) of its probe's lattice.
void check_batch_lattice(const gpu::SurfelBatch& batch, long long index, int surfels_per_probe, Reporter& out) {
  const long long first = batch.first, end = first + batch.count;
  if (first < 0 || end > surfels_per_probe) {
    out.add("batch_lattice", "surfel_batches", index,
            concat("lattice range [", first, ", ", end, ") outside [0, ", surfels_per_probe, ")"));
  }
}

void check_grid_probe(const gpu::Probe& probe, long long index, const ProbeVolume& volume, Reporter& out) {
  if (probe.node != -1)
    out.add("probe_leaf_link", "probes", index, concat("grid probe has node ", probe.node, ", expected -1"));
  if (probe.depth != 0)
    out.add("probe_depth_mismatch", "probes", index, concat("grid probe has depth ", probe.depth, ", expected 0"));
  if (finite_position(probe) && !inside(probe, root_cube(volume.info), out.options().position_epsilon)) {
    out.add("probe_outside_node", "probes", index, "grid probe lies outside the root cube");
  }
}

} // namespace

void check_probes(const ProbeVolume& volume, const OctreeFacts& octree, Reporter& out) {
  check_probe_values(volume, out);
  // Unknown codes (reported by check_volume_info) are checked as octree placement, the stricter case.
  const PlacementKindInfo* kind = placement_kind_for_code(volume.info.placement);
  const bool grid = kind != nullptr && !kind->has_octree; // probes without leaves (node -1)
  std::vector<bool> reported(volume.probes.size(), false);
  const std::vector<int> linked_from =
      grid ? std::vector<int>(volume.probes.size(), -1) : leaf_links(volume, octree, reported, out);
  for (std::size_t i = 0; i < volume.probes.size(); ++i) {
    const gpu::Probe& probe = volume.probes[i];
    const long long index = static_cast<long long>(i);
    if (probe.link == 0) {
      if (probe.node != 0 || probe.depth != 0)
        out.add("free_not_zeroed", "probes", index, "free probe has a node link or depth");
      continue;
    }
    if (grid) {
      check_grid_probe(probe, index, volume, out);
      continue;
    }
    if (reported[i]) continue;
    if (linked_from[i] < 0) {
      out.add("probe_leaf_link", "probes", index,
              concat("allocated, but no reachable leaf links it (node back link ", probe.node, ")"));
      continue;
    }
    if (linked_from[i] != probe.node) {
      out.add("probe_leaf_link", "probes", index,
              concat("node back link is ", probe.node, " but leaf ", linked_from[i], " links it"));
      continue;
    }
    const NodeCube& cube = octree.cubes[probe.node];
    if (probe.depth != cube.depth) {
      out.add("probe_depth_mismatch", "probes", index,
              concat("depth ", probe.depth, ", its node is at depth ", cube.depth));
    }
    if (finite_position(probe) && !inside(probe, cube, out.options().position_epsilon)) {
      out.add("probe_outside_node", "probes", index, concat("position lies outside the cube of node ", probe.node));
    }
  }
}

void check_surfel_batches(const ProbeVolume& volume, Reporter& out) {
  const std::vector<gpu::SurfelBatch>& batches = volume.surfel_batches;
  std::vector<int> owner(batches.size(), -1);
  for (std::size_t p = 0; p < volume.probes.size(); ++p) {
    const int probe = static_cast<int>(p);
    const int link = volume.probes[p].link;
    if (link == 0 || ~link == gpu::PROBE_NO_SURFELS) continue;
    int batch = ~link;
    for (std::size_t length = 0;; ++length) {
      if (batch < 0 || static_cast<std::size_t>(batch) >= batches.size() || batches[batch].link == 0) {
        out.add("batch_link", "probes", probe,
                concat("chain reaches batch ", batch, ", which is out of range or free"));
        break;
      }
      if (owner[batch] == probe || length > batches.size()) {
        out.add("batch_chain_endless", "surfel_batches", batch, concat("the chain of probe ", probe, " loops"));
        break;
      }
      if (owner[batch] >= 0) {
        out.add("batch_shared", "surfel_batches", batch,
                concat("in the chains of probes ", owner[batch], " and ", probe));
        break;
      }
      owner[batch] = probe;
      const gpu::SurfelBatch& b = batches[batch];
      if (b.probe != probe)
        out.add("batch_owner", "surfel_batches", batch, concat("probe field is ", b.probe, ", owner is ", probe));
      if (b.count < 1 || b.count > gpu::SURFELS_PER_BATCH) {
        out.add("batch_count", "surfel_batches", batch, concat("count ", b.count, " outside [1, SURFELS_PER_BATCH]"));
      }
      if (b.link > 0) {
        if (b.link - 1 != probe)
          out.add("batch_owner", "surfel_batches", batch,
                  concat("last link names probe ", b.link - 1, ", owner is ", probe));
        break;
      }
      batch = ~b.link;
    }
  }
  for (std::size_t b = 0; b < batches.size(); ++b) {
    const gpu::SurfelBatch& batch = batches[b];
    const long long index = static_cast<long long>(b);
    if (batch.link == 0) {
      if (batch.probe != 0 || batch.count != 0)
        out.add("free_not_zeroed", "surfel_batches", index, "free batch has an owner or count");
      continue;
    }
    if (owner[b] < 0) out.add("batch_orphan", "surfel_batches", index, "allocated, but in no probe's chain");
    if (batch.count < 1 || batch.count > gpu::SURFELS_PER_BATCH) continue; // batch_count's (or an orphan's)
    check_batch_lattice(batch, index, volume.info.surfels_per_probe, out);
    check_surfels(batch, index, out);
  }
}

void check_probe_index(const ProbeVolume& volume, Reporter& out) {
  if (volume.probe_index.size() != volume.probes.size() + 1) return; // count_mismatch already reported
  std::size_t position = 0;
  for (std::size_t p = 0; p < volume.probes.size(); ++p) {
    if (volume.probes[p].link == 0) continue;
    if (volume.probe_index[position] != static_cast<std::int32_t>(p)) {
      out.add("probe_index_list", "probe_index", static_cast<long long>(position),
              concat("is ", volume.probe_index[position], ", expected allocated probe ", p));
      return;
    }
    ++position;
  }
  for (; position < volume.probe_index.size(); ++position) {
    if (volume.probe_index[position] >= 0) {
      out.add("probe_index_list", "probe_index", static_cast<long long>(position),
              concat("is ", volume.probe_index[position], ", expected a negative end marker"));
      return;
    }
  }
}

} // namespace probebake::formats::detail
