// SVO probe index (nonuniform-probe-placement-svo §4.1). Every voxel at the leaf depth is evaluated
// independently (in parallel, results in index order): it is solid when all its sample points are inside
// geometry; otherwise its candidate probes (the nearest ones) are weighted by visibility from the
// voxel's sample points over squared distance and the best four kept. The tree is then built top-down:
// a cube whose voxels all chose the same probes (or are all empty) becomes one leaf with the mean weights,
// which keeps the index sparse.
#include "svo_builder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"

namespace probebake::bake::detail {
namespace {

constexpr int kCandidates = 12;

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

// Sample points of a voxel: its centre and the centres of its eight octants.
std::array<glm::vec3, 9> voxel_points(glm::vec3 min, float size) {
  std::array<glm::vec3, 9> p;
  p[0] = min + glm::vec3(0.5f * size);
  for (int o = 0; o < 8; ++o)
    p[std::size_t(o) + 1] = min + size * glm::vec3(o & 1 ? 0.75f : 0.25f, o & 2 ? 0.75f : 0.25f, o & 4 ? 0.75f : 0.25f);
  return p;
}

// Inside geometry: most of six axis rays hit back faces of single-sided surfaces (RayHit::inside; the
// back of a double-sided surface is open space).
bool inside_geometry(const scene::RayScene& rays, glm::vec3 p) {
  static const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  int back = 0;
  for (const glm::vec3& d : axes) {
    const auto hit = rays.intersect(p, d);
    back += hit && hit->inside() ? 1 : 0;
  }
  return back >= 4;
}

// Uniform bucket grid over the root cube for nearest-probe queries.
class ProbeBuckets {
public:
  ProbeBuckets(const formats::ProbeVolume& v, int resolution) : volume_(v), n_(resolution), buckets_(std::size_t(n_ * n_ * n_)) {
    for (std::size_t i = 0; i < v.probes.size(); ++i)
      if (v.probes[i].link != 0) buckets_[std::size_t(bucket_index(cell_of(v.probes[i].position)))].push_back(int(i));
  }

  // The k probes nearest to p (ties by index), searching rings of buckets outwards.
  std::vector<int> nearest(glm::vec3 p, int k) const {
    const glm::ivec3 c = cell_of(p);
    std::vector<std::pair<float, int>> found;
    const float cell = volume_.info.root_size / float(n_);
    for (int ring = 0; ring < n_; ++ring) {
      collect_ring(c, ring, p, found);
      if (int(found.size()) >= k) {
        std::sort(found.begin(), found.end());
        if (found[std::size_t(k - 1)].first <= float(ring) * cell * float(ring) * cell) break;
      }
    }
    std::sort(found.begin(), found.end());
    std::vector<int> out;
    for (std::size_t i = 0; i < found.size() && int(i) < k; ++i) out.push_back(found[i].second);
    return out;
  }

private:
  glm::ivec3 cell_of(glm::vec3 p) const {
    const glm::vec3 t = (p - volume_.info.root_min) / volume_.info.root_size * float(n_);
    return glm::clamp(glm::ivec3(glm::floor(t)), glm::ivec3(0), glm::ivec3(n_ - 1));
  }
  int bucket_index(glm::ivec3 c) const { return c.x + n_ * (c.y + n_ * c.z); }

  void collect_ring(glm::ivec3 c, int ring, glm::vec3 p, std::vector<std::pair<float, int>>& found) const {
    for (int z = c.z - ring; z <= c.z + ring; ++z)
      for (int y = c.y - ring; y <= c.y + ring; ++y)
        for (int x = c.x - ring; x <= c.x + ring; ++x) {
          if (std::max({std::abs(x - c.x), std::abs(y - c.y), std::abs(z - c.z)}) != ring) continue;
          if (x < 0 || y < 0 || z < 0 || x >= n_ || y >= n_ || z >= n_) continue;
          for (int probe : buckets_[std::size_t(bucket_index({x, y, z}))]) {
            const glm::vec3 d = volume_.probes[std::size_t(probe)].position - p;
            found.push_back({glm::dot(d, d), probe});
          }
        }
  }

  const formats::ProbeVolume& volume_;
  int n_;
  std::vector<std::vector<int>> buckets_;
};

VoxelPayload evaluate_voxel(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeBuckets& buckets,
                            glm::vec3 min, float size) {
  VoxelPayload out;
  const auto points = voxel_points(min, size);
  std::array<bool, 9> open{};
  bool any_open = false;
  for (std::size_t i = 0; i < points.size(); ++i) any_open |= (open[i] = !inside_geometry(rays, points[i]));
  if (!any_open) {
    out.solid = true;
    return out;
  }
  std::vector<std::pair<float, int>> ranked; // (-weight, probe): sorts best first, ties by index
  for (int probe : buckets.nearest(points[0], kCandidates)) {
    const glm::vec3 target = v.probes[std::size_t(probe)].position;
    int visible = 0, tested = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!open[i]) continue;
      ++tested;
      const glm::vec3 d = target - points[i];
      const float dist = glm::length(d);
      visible += dist == 0.0f || !rays.occluded(points[i], d / dist, 0.0f, dist) ? 1 : 0;
    }
    if (visible == 0) continue;
    const float dist = std::max(glm::length(target - points[0]), 0.5f * size);
    ranked.push_back({-(float(visible) / float(tested)) / (dist * dist), probe});
  }
  std::sort(ranked.begin(), ranked.end());
  ranked.resize(std::min<std::size_t>(ranked.size(), gpu::SVO_PROBES_PER_LEAF));
  // Stored in probe order, not rank order, so that neighbouring voxels that chose the same probes hold
  // the same payload layout and can merge.
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  float total = 0.0f;
  for (const auto& r : ranked) total -= r.first;
  for (std::size_t k = 0; k < ranked.size(); ++k) {
    out.leaf.probes[int(k)] = ranked[k].second;
    out.leaf.weights[int(k)] = -ranked[k].first / total;
  }
  return out;
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
  const int live = int(std::count_if(volume.probes.begin(), volume.probes.end(), [](const gpu::Probe& p) { return p.link != 0; }));
  const ProbeBuckets buckets(volume, std::clamp(int(std::cbrt(double(live) / 2.0)), 1, 32));
  std::vector<VoxelPayload> voxels(std::size_t(n) * std::size_t(n) * std::size_t(n));
  parallel_for(voxels.size(), threads, [&](std::size_t i) {
    const glm::ivec3 c(int(i % std::size_t(n)), int(i / std::size_t(n) % std::size_t(n)), int(i / std::size_t(n * n)));
    voxels[i] = evaluate_voxel(rays, volume, buckets, volume.info.root_min + glm::vec3(c) * size, size);
  });
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

} // namespace probebake::bake::detail
