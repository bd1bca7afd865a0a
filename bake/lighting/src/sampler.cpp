// Irradiance lookup (algorithm in sampler.h): SVO probe index of the non-uniform placement paper §4.1
// with DDGI's smooth back-face weight (Majercik et al. 2019; ddgi-probe-relocation.txt §2.1), and the
// octree thesis's §3.2.4 all-probes baseline with one visibility ray per probe.
#include "probebake/bake/sampler.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"
#include "stencil.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
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

glm::vec3 evaluate_sh(const float* sh27, glm::vec3 n) { return lighting_detail::evaluate_sh<float>(sh27, sh_basis(n)); }

float normal_bias(const gpu::VolumeInfo& info) {
  return 0.5f * info.root_size / float(1 << std::clamp(info.svo_depth, 0, 30));
}

// Integer voxel coordinates at svo_depth; the bits of each, from the top, pick the octant per level.
int find_svo_leaf(const formats::ProbeVolume& volume, glm::vec3 p, int* leaf_depth) {
  const gpu::VolumeInfo& info = volume.info;
  if (volume.svo_nodes.empty() || info.svo_depth < 0 || info.svo_depth > 30) return -1;
  const glm::vec3 t = (p - info.root_min) / info.root_size;
  if (!(t.x >= 0.0f && t.y >= 0.0f && t.z >= 0.0f && t.x <= 1.0f && t.y <= 1.0f && t.z <= 1.0f)) return -1;
  const int n = 1 << info.svo_depth;
  const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor(t * float(n))), glm::ivec3(0), glm::ivec3(n - 1));
  std::size_t node = 0;
  for (int level = info.svo_depth - 1; level >= -1; --level) {
    const int v = volume.svo_nodes[node];
    if (v < 0) {
      if (leaf_depth != nullptr) *leaf_depth = info.svo_depth - 1 - level;
      return std::size_t(~v) < volume.svo_leaves.size() ? ~v : -1;
    }
    if (v == 0 || level < 0) return -1;
    const int octant = ((c.x >> level) & 1) | (((c.y >> level) & 1) << 1) | (((c.z >> level) & 1) << 2);
    node = std::size_t(v) + std::size_t(octant);
    if (node >= volume.svo_nodes.size()) return -1;
  }
  return -1;
}

ProbeStencil svo_stencil(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal) {
  ProbeStencil s;
  const int leaf = find_svo_leaf(volume, position + normal * normal_bias(volume.info));
  if (leaf < 0) return s;
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

glm::vec3 apply_stencil(const formats::ProbeVolume& volume, const ProbeStencil& stencil, glm::vec3 normal) {
  return lighting_detail::apply_stencil<float>(stencil, normal,
                                        [&](int probe) { return volume.probes[std::size_t(probe)].irradiance_sh; });
}

glm::vec3 sample_irradiance(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal,
                            SamplerStats* stats) {
  const ProbeStencil s = svo_stencil(volume, position, normal);
  count(stats, s.empty());
  return apply_stencil(volume, s, normal);
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
    sum += w * glm::max(lighting_detail::evaluate_sh<float>(probe.irradiance_sh, y), glm::vec3(0.0f));
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

} // namespace probebake::bake
