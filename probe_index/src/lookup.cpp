// Irradiance lookup (algorithm in lookup.h): SVO probe index of the non-uniform placement paper §4.1
// with DDGI's smooth back-face weight (Majercik et al. 2019; ddgi-probe-relocation.txt §2.1), and the
// octree thesis's §3.2.4 all-probes baseline with one visibility ray per probe.
#include "probebake/probe_index/lookup.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"
#include "probebake/probe_index/stencil.h"
#include "probebake/formats/error.h"

namespace probebake::probe_index {
namespace {

// ((dot(n, dir) + 1) / 2)^2 + 0.05, dir towards the probe from the shaded point (zero on the probe).
float backface_weight(glm::vec3 normal, glm::vec3 to_probe) {
  const glm::vec3 dir = to_probe * (1.0f / std::sqrt(std::max(glm::dot(to_probe, to_probe), 1e-30f)));
  const float c = 0.5f * (glm::dot(normal, dir) + 1.0f);
  return c * c + 0.05f;
}

void count(SamplerStats* stats, bool miss) {
  if (!stats) return;
  ++stats->samples;
  stats->misses += miss ? 1 : 0;
}

// Runs one lookup per point in parallel; `one(i, miss)` returns the value and reports a miss.
template <class One>
void batch(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals, std::span<glm::vec3> out,
           SamplerStats* stats, int threads, const One& one) {
  if (positions.size() != normals.size() || positions.size() != out.size())
    throw Error(ErrorKind::internal, "sample_irradiance: positions, normals and out differ in size");
  std::vector<unsigned char> missed(positions.size(), 0);
  parallel_for(positions.size(), threads, [&](std::size_t i) {
    bool miss = false;
    out[i] = one(i, miss);
    missed[i] = miss ? 1 : 0;
  });
  if (!stats) return;
  stats->samples += positions.size();
  for (unsigned char m : missed) stats->misses += m;
}

} // namespace

std::array<float, 9> sh_basis(glm::vec3 d) {
  return {kShY0,
          kShY1 * d.y,
          kShY1 * d.z,
          kShY1 * d.x,
          kShY2 * d.x * d.y,
          kShY2 * d.y * d.z,
          kShY20 * (3.0f * d.z * d.z - 1.0f),
          kShY2 * d.x * d.z,
          kShY22 * (d.x * d.x - d.y * d.y)};
}

glm::vec3 evaluate_sh(const float* sh27, glm::vec3 n) { return detail::evaluate_sh<float>(sh27, sh_basis(n)); }

float normal_bias(const gpu::VolumeInfo& info) {
  return 0.5f * info.root_size / float(1 << std::clamp(info.svo_depth, 0, 30));
}

namespace {

// A walk down the SVO towards finest voxel `c` (svo_depth coordinates, in range): `node`'s children split
// on bit `level` of the coordinates (the root's on bit svo_depth - 1; a node at level -1 must be a leaf).
struct Walk {
  std::size_t node = 0;
  int level = 0;
  bool ended = false; // at a leaf (leaf >= 0) or at an empty node or a bad index (leaf -1)
  int leaf = -1;
};

// Walks the levels from w.level down to `last` (inclusive), or until the walk ends.
Walk walk(const formats::ProbeVolume& volume, Walk w, glm::ivec3 c, int last) {
  for (; w.level >= last; --w.level) {
    const int v = volume.svo_nodes[w.node];
    w.ended = v <= 0 || w.level < 0;
    if (w.ended) {
      w.leaf = v < 0 && std::size_t(~v) < volume.svo_leaves.size() ? ~v : -1;
      return w;
    }
    const int octant = ((c.x >> w.level) & 1) | (((c.y >> w.level) & 1) << 1) | (((c.z >> w.level) & 1) << 2);
    w.node = std::size_t(v) + std::size_t(octant);
    if (w.node >= volume.svo_nodes.size()) return {w.node, w.level, true, -1};
  }
  return w;
}

int leaf_of_voxel(const formats::ProbeVolume& volume, glm::ivec3 c, int* leaf_depth) {
  const int svo_depth = volume.info.svo_depth;
  const Walk w = walk(volume, {0, svo_depth - 1}, c, -1);
  if (leaf_depth != nullptr && w.leaf >= 0) *leaf_depth = svo_depth - 1 - w.level;
  return w.leaf;
}

// The leaf of largest weight (the first on ties), -1 when empty.
int heaviest(const BlendedLookup& lookup) {
  int best = -1;
  float best_weight = 0.0f;
  for (int i = 0; i < lookup.count; ++i)
    if (lookup.weights[std::size_t(i)] > best_weight)
      best = lookup.leaves[std::size_t(i)], best_weight = lookup.weights[std::size_t(i)];
  return best;
}

// Leaves `a` and `b` (valid indices) hold a common probe.
bool leaves_share_a_probe(const formats::ProbeVolume& volume, int a, int b) {
  const gpu::SvoLeaf& la = volume.svo_leaves[std::size_t(a)];
  const gpu::SvoLeaf& lb = volume.svo_leaves[std::size_t(b)];
  for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k)
    for (int j = 0; j < gpu::SVO_PROBES_PER_LEAF; ++j)
      if (la.probes[k] >= 0 && la.probes[k] == lb.probes[j]) return true;
  return false;
}

// The entries of `lookup` joined to leaf `root` by chains of leaves that share a probe, in their order.
BlendedLookup connected_to(const formats::ProbeVolume& volume, const BlendedLookup& lookup, int root) {
  std::array<bool, 8> joined{};
  for (bool grew = true; grew;) {
    grew = false;
    for (int i = 0; i < lookup.count; ++i) {
      if (joined[std::size_t(i)]) continue;
      const int leaf = lookup.leaves[std::size_t(i)];
      bool joins = leaf == root || leaves_share_a_probe(volume, leaf, root);
      for (int j = 0; j < lookup.count && !joins; ++j)
        joins = joined[std::size_t(j)] && leaves_share_a_probe(volume, leaf, lookup.leaves[std::size_t(j)]);
      if (joins) joined[std::size_t(i)] = grew = true;
    }
  }
  BlendedLookup out;
  for (int i = 0; i < lookup.count; ++i)
    if (joined[std::size_t(i)]) out.add(lookup.leaves[std::size_t(i)], lookup.weights[std::size_t(i)]);
  return out;
}

bool has_svo(const formats::ProbeVolume& volume) {
  return !volume.svo_nodes.empty() && volume.info.svo_depth >= 0 && volume.info.svo_depth <= 30;
}

} // namespace

int find_svo_leaf(const formats::ProbeVolume& volume, glm::vec3 p, int* leaf_depth) {
  const gpu::VolumeInfo& info = volume.info;
  if (!has_svo(volume)) return -1;
  const glm::vec3 t = (p - info.root_min) / info.root_size;
  if (!(t.x >= 0.0f && t.y >= 0.0f && t.z >= 0.0f && t.x <= 1.0f && t.y <= 1.0f && t.z <= 1.0f)) return -1;
  const int n = 1 << info.svo_depth;
  return leaf_of_voxel(volume, glm::clamp(glm::ivec3(glm::floor(t * float(n))), glm::ivec3(0), glm::ivec3(n - 1)),
                       leaf_depth);
}

void BlendedLookup::add(int leaf, float weight) {
  for (int i = 0; i < count; ++i)
    if (leaves[std::size_t(i)] == leaf) {
      weights[std::size_t(i)] += weight;
      return;
    }
  leaves[std::size_t(count)] = leaf;
  weights[std::size_t(count++)] = weight;
}

BlendedLookup BlendedLookup::normalised() const {
  BlendedLookup out = *this;
  float sum = 0.0f;
  for (int i = 0; i < count; ++i) sum += weights[std::size_t(i)];
  for (int i = 0; i < count; ++i) out.weights[std::size_t(i)] = weights[std::size_t(i)] / sum;
  return out;
}

bool leaf_serves(const formats::ProbeVolume& volume, int leaf) {
  if (leaf < 0 || std::size_t(leaf) >= volume.svo_leaves.size()) return false;
  const gpu::SvoLeaf& l = volume.svo_leaves[std::size_t(leaf)];
  for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k)
    if (l.probes[k] >= 0 && std::size_t(l.probes[k]) < volume.probes.size() && l.weights[k] > 0.0f) return true;
  return false;
}

ProbeStencil leaf_stencil(const formats::ProbeVolume& volume, int leaf, glm::vec3 position, glm::vec3 normal) {
  ProbeStencil s;
  if (leaf < 0 || std::size_t(leaf) >= volume.svo_leaves.size()) return s;
  const gpu::SvoLeaf& l = volume.svo_leaves[std::size_t(leaf)];
  glm::vec4 w(0.0f);
  float sum = 0.0f;
  for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k) {
    const int probe = l.probes[k];
    if (probe < 0 || std::size_t(probe) >= volume.probes.size()) continue;
    w[k] = l.weights[k] * backface_weight(normal, volume.probes[std::size_t(probe)].position - position);
    sum += w[k];
  }
  if (!(sum > 0.0f)) return s;
  int used = 0;
  for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k) {
    if (w[k] <= 0.0f) continue;
    s.probes[used] = l.probes[k];
    s.weights[used++] = w[k] / sum;
  }
  return s;
}

ProbeStencil svo_stencil(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal) {
  return leaf_stencil(volume, find_svo_leaf(volume, position + normal * normal_bias(volume.info)), position, normal);
}

BlendedLookup blended_lookup(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal) {
  BlendedLookup out;
  if (!has_svo(volume)) return out;
  const gpu::VolumeInfo& info = volume.info;
  const float bias = normal_bias(info);
  const glm::vec3 biased = position + normal * bias;
  const glm::vec3 rel = (biased - info.root_min) / info.root_size;
  if (!(glm::all(glm::greaterThanEqual(rel, glm::vec3(0.0f))) && glm::all(glm::lessThanEqual(rel, glm::vec3(1.0f)))))
    return out; // outside the root cube (or not finite): a miss, as the leaf lookup
  const int n = 1 << info.svo_depth;
  const float voxel = info.root_size / float(n);
  // The eight finest voxel centres around p', clamped to the root cube (centres beyond it repeat the edge).
  const glm::vec3 g = rel * float(n) - 0.5f;
  const glm::vec3 floor_g = glm::floor(g);
  const glm::vec3 f = g - floor_g;
  const glm::ivec3 lo = glm::clamp(glm::ivec3(floor_g), glm::ivec3(0), glm::ivec3(n - 1));
  const glm::ivec3 hi = glm::clamp(glm::ivec3(floor_g) + 1, glm::ivec3(0), glm::ivec3(n - 1));
  // The corners share the bits above the highest one in which lo and hi differ: one walk down to there.
  const glm::ivec3 differ = lo ^ hi;
  const int spread = std::bit_width(unsigned(differ.x | differ.y | differ.z));
  const Walk top = walk(volume, {0, info.svo_depth - 1}, lo, spread);
  const Walk next = walk(volume, top, lo, top.level); // one level more: a leaf there holds every corner
  if (top.ended || next.ended) {
    const int leaf = top.ended ? top.leaf : next.leaf;
    if (leaf_serves(volume, leaf)) out.add(leaf, 1.0f);
    return out.normalised();
  }
  // p''s own voxel is one of the corners.
  const glm::ivec3 own = glm::clamp(glm::ivec3(glm::floor(rel * float(n))), glm::ivec3(0), glm::ivec3(n - 1));
  int home = -1;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::bvec3 up((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
    const glm::ivec3 c(up.x ? hi.x : lo.x, up.y ? hi.y : lo.y, up.z ? hi.z : lo.z);
    const glm::vec3 t(up.x ? f.x : 1.0f - f.x, up.y ? f.y : 1.0f - f.y, up.z ? f.z : 1.0f - f.z);
    const glm::vec3 centre = info.root_min + (glm::vec3(c) + 0.5f) * voxel;
    // Centres behind the surface's plane do not blend in: they may lie past a thin wall.
    const float side = std::clamp(glm::dot(centre - position, normal) / bias, 0.0f, 1.0f);
    const float weight = t.x * t.y * t.z * side;
    const bool is_own = c == own && home < 0;
    if (!(weight > 0.0f) && !is_own) continue;
    const int leaf = walk(volume, top, c, -1).leaf;
    if (is_own) home = leaf;
    if (weight > 0.0f && leaf_serves(volume, leaf)) out.add(leaf, weight);
  }
  const int root = leaf_serves(volume, home) ? home : heaviest(out);
  if (root < 0) return out;
  out = connected_to(volume, out, root);
  if (out.count == 0) out.add(root, 1.0f);
  return out.normalised();
}

glm::vec3 apply_stencil(const formats::ProbeVolume& volume, const ProbeStencil& stencil, glm::vec3 normal) {
  return detail::apply_stencil<float>(stencil, normal,
                                      [&](int probe) { return volume.probes[std::size_t(probe)].irradiance_sh; });
}

ProbeBlend probe_blend(const formats::ProbeVolume& volume, const BlendedLookup& lookup, glm::vec3 position,
                       glm::vec3 normal) {
  ProbeBlend out;
  std::array<float, ProbeBlend::kCapacity> backface{};
  for (int i = 0; i < lookup.count; ++i) {
    const gpu::SvoLeaf& l = volume.svo_leaves[std::size_t(lookup.leaves[std::size_t(i)])];
    std::array<int, gpu::SVO_PROBES_PER_LEAF> slot{-1, -1, -1, -1};
    glm::vec4 w(0.0f);
    float sum = 0.0f;
    for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k) {
      const int probe = l.probes[k];
      if (probe < 0 || std::size_t(probe) >= volume.probes.size()) continue;
      int j = 0;
      while (j < out.count && out.probes[std::size_t(j)] != probe) ++j;
      if (j == out.count) {
        out.probes[std::size_t(j)] = probe;
        out.weights[std::size_t(j)] = 0.0f;
        backface[std::size_t(j)] = backface_weight(normal, volume.probes[std::size_t(probe)].position - position);
        ++out.count;
      }
      slot[std::size_t(k)] = j;
      w[k] = l.weights[k] * backface[std::size_t(j)];
      sum += w[k];
    }
    if (!(sum > 0.0f)) continue;
    for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k)
      if (slot[std::size_t(k)] >= 0)
        out.weights[std::size_t(slot[std::size_t(k)])] += lookup.weights[std::size_t(i)] * (w[k] / sum);
  }
  return out;
}

glm::vec3 apply_blend(const formats::ProbeVolume& volume, const ProbeBlend& blend, glm::vec3 normal) {
  glm::vec3 e(0.0f);
  if (blend.count == 0) return e;
  const std::array<float, 9> y = sh_basis(normal);
  for (int j = 0; j < blend.count; ++j) {
    const gpu::Probe& probe = volume.probes[std::size_t(blend.probes[std::size_t(j)])];
    e += blend.weights[std::size_t(j)] * glm::max(detail::evaluate_sh<float>(probe.irradiance_sh, y), glm::vec3(0.0f));
  }
  return e;
}

glm::vec3 sample_irradiance(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal,
                            SamplerStats* stats) {
  const BlendedLookup lookup = blended_lookup(volume, position, normal);
  count(stats, lookup.count == 0);
  return apply_blend(volume, probe_blend(volume, lookup, position, normal), normal);
}

glm::vec3 sample_irradiance_all_probes(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                                       glm::vec3 position, glm::vec3 normal, SamplerStats* stats) {
  const float bias = normal_bias(volume.info);
  const glm::vec3 biased = position + normal * bias;
  const std::array<float, 9> y = sh_basis(normal);
  glm::vec3 sum(0.0f);
  float total = 0.0f;
  for (const gpu::Probe& probe : volume.probes) {
    if (probe.link == 0) continue;
    const glm::vec3 to = probe.position - biased;
    const float dist = glm::length(to);
    if (dist > 0.0f && rays.occluded(biased, to / dist, 0.0f, dist)) continue;
    const glm::vec3 d = probe.position - position;
    const float w = backface_weight(normal, d) / std::max(glm::dot(d, d), bias * bias);
    sum += w * glm::max(detail::evaluate_sh<float>(probe.irradiance_sh, y), glm::vec3(0.0f));
    total += w;
  }
  count(stats, !(total > 0.0f));
  return total > 0.0f ? sum / total : glm::vec3(0.0f);
}

void sample_irradiance(const formats::ProbeVolume& volume, std::span<const glm::vec3> positions,
                       std::span<const glm::vec3> normals, std::span<glm::vec3> out, SamplerStats* stats, int threads) {
  batch(positions, normals, out, stats, threads, [&](std::size_t i, bool& miss) {
    SamplerStats one;
    const glm::vec3 e = sample_irradiance(volume, positions[i], normals[i], &one);
    miss = one.misses > 0;
    return e;
  });
}

void sample_irradiance_all_probes(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                                  std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                  std::span<glm::vec3> out, SamplerStats* stats, int threads) {
  batch(positions, normals, out, stats, threads, [&](std::size_t i, bool& miss) {
    SamplerStats one;
    const glm::vec3 e = sample_irradiance_all_probes(volume, rays, positions[i], normals[i], &one);
    miss = one.misses > 0;
    return e;
  });
}

} // namespace probebake::probe_index
