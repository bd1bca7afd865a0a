// Bake-time lighting (lighting.h): trace and cache every probe's rays once (octree thesis §3.2.2 L1),
// then re-light the cached hits from the previous sweep's probes until the probes stop changing (the
// thesis's L2 step run to convergence, DDGI's probe-to-probe recursion for multiple bounces).
#include "probebake/lighting/lighting.h"

#include <chrono>
#include <cmath>

#include "hit_cache.h"
#include "iteration.h"
#include "probebake/formats/error.h"

namespace probebake::lighting {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void require(bool ok, const char* message) {
  if (!ok) throw Error(ErrorKind::usage, message);
}

} // namespace

void check_lighting_settings(const LightingSettings& s) {
  require(s.rays >= 1 && s.rays <= 65536, "lighting rays must be in [1, 65536]");
  require(std::isfinite(s.tolerance) && s.tolerance > 0.0f && s.tolerance < 1.0f,
          "lighting tolerance must be in (0, 1)");
  require(s.max_iterations >= 1, "lighting max iterations must be >= 1");
  require(s.threads >= 0, "threads must be >= 0");
  require(s.emitter_samples >= 1 && s.emitter_samples <= 65536, "lighting emitter samples must be in [1, 65536]");
}

LightingReport bake_lighting(const scene::Scene& scene, const scene::RayScene& rays, formats::ProbeVolume& volume,
                             const LightingSettings& settings) {
  check_lighting_settings(settings);
  const auto start = Clock::now();
  LightingReport report;
  const detail::HitCache cache = detail::build_hit_cache(scene, rays, volume, settings);
  report.probes = int(cache.probes.size());
  report.rays = cache.records.size();
  report.backface_hits = cache.backface_hits;
  report.misses = cache.misses;
  report.indirect_misses = cache.indirect_misses;
  report.trace_seconds = seconds_since(start);

  const auto iterate_start = Clock::now();
  detail::ShBuffer sh(gpu::PROBE_SH_FLOATS * volume.probes.size(), 0.0);
  if (!cache.probes.empty())
    detail::solve(cache, settings, sh, report);
  else
    report.converged = true;
  detail::measure_noise(cache, sh, report);
  for (int p : cache.probes)
    for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v)
      volume.probes[std::size_t(p)].irradiance_sh[v] =
          float(sh[gpu::PROBE_SH_FLOATS * std::size_t(p) + std::size_t(v)]);
  report.iterate_seconds = seconds_since(iterate_start);
  report.seconds = seconds_since(start);
  return report;
}

} // namespace probebake::lighting
