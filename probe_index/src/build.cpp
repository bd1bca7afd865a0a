// SVO probe index (nonuniform-probe-placement-svo §4.1). Every voxel at the leaf depth is evaluated
// independently (in parallel, results in index order): it is solid when all its sample points are inside
// geometry; otherwise its candidate probes (the nearest ones) are weighted by visibility from its open
// sample points over squared distance and the best four kept. When a surface splits those points into
// regions that see different groups of probes, one group serves the voxel (rank_by_group). Voxels left empty
// though open take their neighbours' probes where they see them (fill_uncovered). The tree is then built
// top-down: a cube whose voxels all chose the same probes (or are all empty) becomes one leaf with the mean
// weights, which keeps the index sparse.
#include "probebake/probe_index/build.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"
#include "probe_buckets.h"
#include "probe_groups.h"
#include "voxel_samples.h"

namespace probebake::probe_index {
using detail::DisjointSets;
using detail::GroupVotes;
using detail::Points;
using detail::PointSet;
using detail::probe_groups;
using detail::ProbeBuckets;
using detail::ProbeGroups;
using detail::sample_voxel;
using detail::sees;
using detail::VoxelSamples;
namespace {

constexpr int kCandidates = 12;
constexpr int kFarCandidates = 48; // when a region of the voxel sees none of the nearest 12

struct VoxelPayload {
  bool solid = false;
  gpu::SvoLeaf leaf{glm::ivec4(-1), glm::vec4(0.0f)};
  bool empty() const { return solid || leaf.probes.x < 0; }
  // Same probes (or both empty): one leaf serves both, with mean weights. The weights are selection
  // quality for §4.1's ranking; the sampler interpolates by position at run time.
  bool mergeable(const VoxelPayload& o) const {
    if (empty() || o.empty()) return empty() && o.empty();
    return leaf.probes == o.leaf.probes;
  }
};

// The voxel's open sample points grouped into open regions: points joined by unoccluded segments share a
// region. Largest region first (ties: the one holding the lowest index, the centre first).
std::vector<PointSet> open_regions(const scene::RayScene& rays, const Points& points, const PointSet& open) {
  constexpr int count = detail::kVoxelPoints;
  DisjointSets sets(count);
  const auto root = [&](int i) { return sets.root(i); };
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j) {
      if (!open[std::size_t(i)] || !open[std::size_t(j)] || root(i) == root(j)) continue;
      if (sees(rays, points[std::size_t(i)], points[std::size_t(j)])) sets.join(i, j);
    }
  std::vector<std::pair<int, int>> order; // (-size, root)
  for (int r = 0; r < count; ++r) {
    int size = 0;
    for (int i = 0; i < count; ++i) size += open[std::size_t(i)] && root(i) == r ? 1 : 0;
    if (size > 0) order.push_back({-size, r});
  }
  std::sort(order.begin(), order.end());
  std::vector<PointSet> regions;
  for (const auto& [size, r] : order) {
    PointSet in{};
    for (int i = 0; i < count; ++i) in[std::size_t(i)] = open[std::size_t(i)] && root(i) == r;
    regions.push_back(in);
  }
  return regions;
}

// Candidate probes seen from the region's points, best first: (-weight, probe), weight = the fraction of
// the points that see the probe over its squared distance from the voxel's centre.
std::vector<std::pair<float, int>> rank_probes(const scene::RayScene& rays, const formats::ProbeVolume& v,
                                               const std::vector<int>& candidates, const Points& points,
                                               const PointSet& region, float size) {
  std::vector<std::pair<float, int>> ranked; // sorts best first, ties by index
  for (int probe : candidates) {
    const glm::vec3 target = v.probes[std::size_t(probe)].position;
    int visible = 0, tested = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!region[i]) continue;
      ++tested;
      visible += sees(rays, points[i], target) ? 1 : 0;
    }
    if (visible == 0) continue;
    const float dist = std::max(glm::length(target - points[0]), 0.5f * size);
    ranked.push_back({-(float(visible) / float(tested)) / (dist * dist), probe});
  }
  std::sort(ranked.begin(), ranked.end());
  return ranked;
}

// The probes the region's points see among the nearest kCandidates, or, when it sees none of those (they
// lie behind the light box beside a ceiling voxel, or in the sealed box itself), among the nearest
// kFarCandidates: a voxel is left empty (a hole in the lookup) only when no probe near it is visible.
std::vector<std::pair<float, int>> rank_nearby(const scene::RayScene& rays, const formats::ProbeVolume& v,
                                               const ProbeBuckets& buckets, const Points& points,
                                               const PointSet& region, float size) {
  std::vector<std::pair<float, int>> ranked =
      rank_probes(rays, v, buckets.nearest(points[0], kCandidates), points, region, size);
  if (ranked.empty()) ranked = rank_probes(rays, v, buckets.nearest(points[0], kFarCandidates), points, region, size);
  return ranked;
}

// A voxel that a surface cuts into open regions whose probes lie in different groups is served by one
// group alone: the one with the most lookups to serve, estimated as the voxel's points that see it times
// the group's probes. The points are the share of the voxel's volume on that side; the probe count weighs
// out spaces no player reaches (the inside of a sealed light box holds a dozen probes against thousands in
// the room), while two rooms either side of a wall compete by volume. Testing visibility from all open
// points at once let probes seen only from a sliver of the voxel into its stencil by their short distance,
// and lookups on the other side blended light from a space they cannot see (issue #39: 150x the reference
// on a ceiling beside a closed emissive box). Within one group (a thin surface in open space, the common
// case) the stencil is tested from every open point, as it always was.
std::optional<std::vector<std::pair<float, int>>>
rank_by_group(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeBuckets& buckets,
              const ProbeGroups& groups, const Points& points, const std::vector<PointSet>& regions, float size) {
  std::vector<std::vector<std::pair<float, int>>> seen;
  GroupVotes votes(groups);
  for (const PointSet& region : regions) {
    seen.push_back(rank_nearby(rays, v, buckets, points, region, size));
    const int region_points = int(std::count(region.begin(), region.end(), true));
    std::vector<int> counted;
    for (const auto& [weight, probe] : seen.back()) {
      const int g = groups.group[std::size_t(probe)];
      if (std::find(counted.begin(), counted.end(), g) != counted.end()) continue;
      counted.push_back(g);
      votes.vote(g, region_points);
    }
  }
  if (votes.groups_voted() < 2) return std::nullopt;
  const int best = votes.winner();
  for (std::vector<std::pair<float, int>>& ranked : seen) {
    std::erase_if(ranked, [&](const auto& r) { return groups.group[std::size_t(r.second)] != best; });
    if (!ranked.empty()) return std::move(ranked);
  }
  return std::nullopt; // not reached: some region saw the best group
}

// The best four of `ranked` (best first), stored in probe order, not rank order, so that neighbouring voxels
// that chose the same probes hold the same payload layout and can merge.
VoxelPayload payload_of(std::vector<std::pair<float, int>> ranked) {
  VoxelPayload out;
  ranked.resize(std::min<std::size_t>(ranked.size(), gpu::SVO_PROBES_PER_LEAF));
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  float total = 0.0f;
  for (const auto& r : ranked) total -= r.first;
  for (std::size_t k = 0; k < ranked.size(); ++k) {
    out.leaf.probes[int(k)] = ranked[k].second;
    out.leaf.weights[int(k)] = -ranked[k].first / total;
  }
  return out;
}

// The group a payload's probes belong to (one group per payload), -1 for an empty one.
int payload_group(const VoxelPayload& p, const ProbeGroups& groups) {
  return p.empty() ? -1 : groups.group[std::size_t(p.leaf.probes.x)];
}

VoxelPayload evaluate_samples(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeBuckets& buckets,
                              const ProbeGroups& groups, const VoxelSamples& samples, float size) {
  if (!samples.any_open) return VoxelPayload{true};
  const Points& points = samples.points;
  const PointSet& open = samples.open;
  std::vector<std::pair<float, int>> ranked = rank_nearby(rays, v, buckets, points, open, size);
  // Regions are looked for only when the open points see more than one group: the common voxel pays
  // nothing for them.
  const bool one_group = std::all_of(ranked.begin(), ranked.end(), [&](const auto& r) {
    return groups.group[std::size_t(r.second)] == groups.group[std::size_t(ranked.front().second)];
  });
  if (!one_group) {
    const std::vector<PointSet> regions = open_regions(rays, points, open);
    if (regions.size() > 1)
      if (auto by_group = rank_by_group(rays, v, buckets, groups, points, regions, size)) ranked = std::move(*by_group);
  }
  return payload_of(std::move(ranked));
}

// A voxel that a minor group serves may be a cavity's voxel whose nine sample points all fell inside the
// cavity while a sliver of the room beside its wall is in it too (issue #39: the light box at SVO depth 4,
// where a voxel is taller than the box: a receiver on the ceiling 4 mm beside the box took the box's inside,
// 135 W/m^2 against 0.73). Its octants are evaluated as voxels of their own and vote as rank_by_group's
// regions do (open points x group size): when a larger group wins, the voxel takes the payload of the
// octant with the most open points in it (the first on ties). Voxels of the largest groups pay nothing.
VoxelPayload evaluate_voxel(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeBuckets& buckets,
                            const ProbeGroups& groups, glm::vec3 min, float size) {
  VoxelPayload payload = evaluate_samples(rays, v, buckets, groups, sample_voxel(rays, min, glm::vec3(size)), size);
  const int own = payload_group(payload, groups);
  if (!groups.minor(own)) return payload;
  GroupVotes votes(groups);
  std::array<VoxelPayload, 8> octants;
  std::array<int, 8> open_points{};
  for (int o = 0; o < 8; ++o) {
    const glm::vec3 at = min + 0.5f * size * glm::vec3(float(o & 1), float((o >> 1) & 1), float((o >> 2) & 1));
    const VoxelSamples samples = sample_voxel(rays, at, glm::vec3(0.5f * size));
    octants[std::size_t(o)] = evaluate_samples(rays, v, buckets, groups, samples, 0.5f * size);
    open_points[std::size_t(o)] = int(std::count(samples.open.begin(), samples.open.end(), true));
    const int g = payload_group(octants[std::size_t(o)], groups);
    if (g >= 0) votes.vote(g, open_points[std::size_t(o)]);
  }
  const int best = votes.winner();
  if (best < 0 || best == own) return payload;
  int chosen = -1;
  for (int o = 0; o < 8; ++o)
    if (payload_group(octants[std::size_t(o)], groups) == best &&
        (chosen < 0 || open_points[std::size_t(o)] > open_points[std::size_t(chosen)]))
      chosen = o;
  return octants[std::size_t(chosen)];
}

// A voxel whose open points see none of its 48 nearest probes was left empty: a hole in the lookup. Those
// probes can all lie in a sealed cavity beside it (issue #39: CornellBox.glb's short block is closed and
// double-sided, its inside holds the probes nearest to the two layers of voxels just above its top, and
// receivers on the top missed). Such a voxel ranks the probes its 26 neighbours chose instead, in passes
// outwards from the voxels that have probes: each pass tries the empty open voxels beside the ones the pass
// before filled, reading the payloads as they were when it began (the result does not depend on the thread
// count). A voxel whose open points see none of its neighbours' probes stays empty (outside every room).
void fill_uncovered(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeGroups& groups, int n,
                    float size, std::vector<VoxelPayload>& voxels, int threads) {
  const auto coords = [n](std::size_t i) {
    return glm::ivec3(int(i % std::size_t(n)), int(i / std::size_t(n) % std::size_t(n)), int(i / std::size_t(n * n)));
  };
  const auto for_each_neighbour = [&](std::size_t i, auto&& f) {
    const glm::ivec3 c = coords(i);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const glm::ivec3 nc = c + glm::ivec3(dx, dy, dz);
          if (nc == c || glm::any(glm::lessThan(nc, glm::ivec3(0))) ||
              glm::any(glm::greaterThanEqual(nc, glm::ivec3(n))))
            continue;
          f(std::size_t(nc.x + n * (nc.y + n * nc.z)));
        }
  };
  std::vector<std::size_t> fresh; // voxels that gained probes in the last pass (at first: every served one)
  for (std::size_t i = 0; i < voxels.size(); ++i)
    if (!voxels[i].empty()) fresh.push_back(i);
  while (!fresh.empty()) {
    std::vector<std::size_t> frontier;
    for (std::size_t i : fresh)
      for_each_neighbour(i, [&](std::size_t j) {
        if (!voxels[j].solid && voxels[j].empty()) frontier.push_back(j);
      });
    std::sort(frontier.begin(), frontier.end());
    frontier.erase(std::unique(frontier.begin(), frontier.end()), frontier.end());
    std::vector<VoxelPayload> filled(frontier.size());
    parallel_for(frontier.size(), threads, [&](std::size_t k) {
      std::vector<int> candidates;
      for_each_neighbour(frontier[k], [&](std::size_t j) {
        for (int slot = 0; slot < gpu::SVO_PROBES_PER_LEAF; ++slot)
          if (voxels[j].leaf.probes[slot] >= 0) candidates.push_back(voxels[j].leaf.probes[slot]);
      });
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      const VoxelSamples samples =
          sample_voxel(rays, v.info.root_min + glm::vec3(coords(frontier[k])) * size, glm::vec3(size));
      auto ranked = rank_probes(rays, v, candidates, samples.points, samples.open, size);
      if (ranked.empty()) return;
      // One group, as evaluate_voxel keeps: the largest seen (a sealed cavity's probes do not mix in).
      const auto group_of = [&](const auto& r) { return groups.group[std::size_t(r.second)]; };
      const int largest = group_of(*std::max_element(ranked.begin(), ranked.end(), [&](const auto& a, const auto& b) {
        const int ga = group_of(a), gb = group_of(b);
        return groups.size[std::size_t(ga)] < groups.size[std::size_t(gb)] ||
               (groups.size[std::size_t(ga)] == groups.size[std::size_t(gb)] && ga > gb);
      }));
      std::erase_if(ranked, [&](const auto& r) { return group_of(r) != largest; });
      filled[k] = payload_of(std::move(ranked));
    });
    fresh.clear();
    for (std::size_t k = 0; k < frontier.size(); ++k)
      if (!filled[k].empty()) {
        voxels[frontier[k]] = filled[k];
        fresh.push_back(frontier[k]);
      }
  }
}

struct Builder {
  int depth_max;
  int n;
  const std::vector<VoxelPayload>& voxels;
  formats::ProbeVolume& volume;

  // One payload for the whole subtree when all its voxels can merge (mean weights), else nullopt.
  std::optional<VoxelPayload> uniform(int depth, glm::ivec3 origin) const {
    const int span = 1 << (depth_max - depth);
    const VoxelPayload& first = voxels[std::size_t(origin.x + n * (origin.y + n * origin.z))];
    glm::vec4 sum(0.0f);
    for (int z = 0; z < span; ++z)
      for (int y = 0; y < span; ++y)
        for (int x = 0; x < span; ++x) {
          const VoxelPayload& v = voxels[std::size_t(origin.x + x + n * (origin.y + y + n * (origin.z + z)))];
          if (!v.mergeable(first)) return std::nullopt;
          sum += v.leaf.weights;
        }
    VoxelPayload merged = first;
    if (!merged.empty()) merged.leaf.weights = sum / (sum.x + sum.y + sum.z + sum.w);
    return merged;
  }

  int leaf_value(const VoxelPayload& p) {
    if (p.empty()) return 0;
    volume.svo_leaves.push_back(p.leaf);
    return ~int(volume.svo_leaves.size() - 1);
  }

  // Writes node `index` for the cube at `origin` (voxel coordinates) of level `depth`.
  void build(std::size_t index, int depth, glm::ivec3 origin) {
    if (auto u = uniform(depth, origin)) {
      volume.svo_nodes[index] = leaf_value(*u);
      return;
    }
    const auto first_child = volume.svo_nodes.size();
    volume.svo_nodes.resize(first_child + 8, 0);
    volume.svo_nodes[index] = int(first_child);
    const int half = 1 << (depth_max - depth - 1);
    for (int o = 0; o < 8; ++o)
      build(first_child + std::size_t(o), depth + 1, origin + half * glm::ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1));
  }
};

} // namespace

SvoStats build_svo(const scene::RayScene& rays, formats::ProbeVolume& volume, int svo_depth, int threads) {
  const int n = 1 << svo_depth;
  const float size = volume.info.root_size / float(n);
  // About two probes per bucket: the ring search then touches few empty buckets.
  const int live =
      int(std::count_if(volume.probes.begin(), volume.probes.end(), [](const gpu::Probe& p) { return p.link != 0; }));
  const ProbeBuckets buckets(volume, std::clamp(int(std::cbrt(double(live) / 2.0)), 1, 32));
  const ProbeGroups groups = probe_groups(rays, volume, buckets, threads);
  std::vector<VoxelPayload> voxels(std::size_t(n) * std::size_t(n) * std::size_t(n));
  parallel_for(voxels.size(), threads, [&](std::size_t i) {
    const glm::ivec3 c(int(i % std::size_t(n)), int(i / std::size_t(n) % std::size_t(n)), int(i / std::size_t(n * n)));
    voxels[i] = evaluate_voxel(rays, volume, buckets, groups, volume.info.root_min + glm::vec3(c) * size, size);
  });
  fill_uncovered(rays, volume, groups, n, size, voxels, threads);
  SvoStats stats;
  stats.voxels_evaluated = int(voxels.size());
  for (const auto& v : voxels) {
    stats.solid_voxels += v.solid ? 1 : 0;
    stats.uncovered_voxels += !v.solid && v.empty() ? 1 : 0;
  }
  volume.svo_nodes.assign(1, 0);
  volume.svo_leaves.clear();
  Builder builder{svo_depth, n, voxels, volume};
  builder.build(0, 0, glm::ivec3(0));
  return stats;
}

} // namespace probebake::probe_index
