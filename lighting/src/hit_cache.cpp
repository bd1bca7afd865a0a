// Probe ray tracing and per-hit caching for the lighting iteration (see hit_cache.h).
#include "hit_cache.h"

#include <cmath>

#include <fmt/core.h>

#include "probebake/lighting/direct_light.h"
#include "probebake/common/parallel.h"
#include "probebake/common/lattice.h"
#include "probebake/formats/error.h"

namespace probebake::lighting::detail {
namespace {

constexpr float kInvPi = 0.318309886f;

struct ProbeCounts {
  std::size_t backface = 0, misses = 0, indirect_misses = 0;
};

std::vector<std::array<float, 9>> projection_table(const std::vector<glm::vec3>& directions) {
  static constexpr float band[9] = {probe_index::kShBand0, probe_index::kShBand1, probe_index::kShBand1,
                                    probe_index::kShBand1, probe_index::kShBand2, probe_index::kShBand2,
                                    probe_index::kShBand2, probe_index::kShBand2, probe_index::kShBand2};
  const float weight = 4.0f * 3.14159265f / float(directions.size());
  std::vector<std::array<float, 9>> table;
  for (const glm::vec3& d : directions) {
    std::array<float, 9> y = probe_index::sh_basis(d);
    for (std::size_t k = 0; k < 9; ++k) y[k] *= weight * band[k];
    table.push_back(y);
  }
  return table;
}

// With emissive_as_lights the emitters' own radiance is left out of the probes (shading points add it
// through direct_irradiance), but the light they cast on this hit stays in, through E_direct. A hit on
// either side of a double-sided surface is shaded with the normal of the side the ray arrived at.
HitRecord shade_hit(const scene::Scene& scene, const formats::ProbeVolume& volume, const DirectLighting& direct,
                    bool emission_seen, glm::vec3 point, const scene::RayHit& hit) {
  HitRecord h;
  h.normal = hit.facing_normal();
  h.reflect = scene.triangle_albedo[hit.triangle] * kInvPi;
  h.base = (emission_seen ? scene.triangle_emission[hit.triangle] : glm::vec3(0.0f)) +
           h.reflect * direct.irradiance(point, h.normal);
  h.stencil = probe_index::svo_stencil(volume, point, h.normal);
  return h;
}

void check_finite(const HitRecord& h, int probe, std::size_t ray) {
  if (std::isfinite(h.base.x) && std::isfinite(h.base.y) && std::isfinite(h.base.z)) return;
  throw Error(ErrorKind::input, fmt::format("lighting: probe {} ray {}: emitted plus direct radiance at the hit is not "
                                            "finite (emission or light intensity beyond 32-bit float range?)",
                                            probe, ray));
}

} // namespace

HitCache build_hit_cache(const scene::Scene& scene, const scene::RayScene& rays, const formats::ProbeVolume& volume,
                         const LightingSettings& settings) {
  HitCache cache;
  cache.rays_per_probe = settings.rays;
  for (std::size_t i = 0; i < volume.probes.size(); ++i)
    if (volume.probes[i].link != 0) cache.probes.push_back(int(i));
  const std::vector<glm::vec3> directions = lattice_directions(Lattice::fibonacci, settings.rays);
  cache.projection = projection_table(directions);
  const std::size_t r = directions.size();
  cache.records.resize(cache.probes.size() * r);
  std::vector<ProbeCounts> counts(cache.probes.size());
  const DirectLighting direct(scene, rays, settings);
  parallel_for(cache.probes.size(), settings.threads, [&](std::size_t i) {
    const glm::vec3 origin = volume.probes[std::size_t(cache.probes[i])].position;
    for (std::size_t j = 0; j < r; ++j) {
      HitRecord& h = cache.records[i * r + j];
      const auto hit = rays.intersect(origin, directions[j]);
      if (!hit) {
        h.base = scene.sky.radiance(directions[j]);
        ++counts[i].misses;
      } else if (hit->inside()) { // the back of a single-sided surface: black and absorbing
        ++counts[i].backface;
      } else {
        h = shade_hit(scene, volume, direct, !settings.emissive_as_lights, origin + hit->distance * directions[j],
                      *hit);
        counts[i].indirect_misses += h.stencil.empty() ? 1 : 0;
        check_finite(h, cache.probes[i], j);
      }
    }
  });
  for (const ProbeCounts& c : counts) {
    cache.backface_hits += c.backface;
    cache.misses += c.misses;
    cache.indirect_misses += c.indirect_misses;
  }
  return cache;
}

} // namespace probebake::lighting::detail
