// Bake-time lighting: fills every live probe's irradiance_sh (L2 SH of irradiance, see lookup.h) with
// the light arriving from the scene's surfaces, by fixed-point iteration over cached probe rays.
//
// References: octree thesis §3.2.2 (L2 "light surfels and probe": surfel hits lit directly and from the
// probes, accumulated into the probe), DDGI (Majercik et al. 2019; DDGI relocation paper §2.1) for the
// probe-to-probe recursion that gives multiple bounces. Algorithm and choices: docs/LIGHTING.md.
//
// Each live probe traces `rays` Fibonacci directions over the full sphere to the nearest hit. Radiance
// leaving a hit towards the probe: back face of a single-sided surface 0 (inside geometry); miss
// the scene's sky (scene.sky, docs/LIGHTING.md "The sky"); front face, or either face of a double-sided (glTF doubleSided) surface with the normal
// facing the ray,
//   L = L_e + albedo / pi * (E_direct + E_indirect),
// E_direct = direct_irradiance() (punctual lights with a shadow ray; with emissive_as_lights also the
// emissive triangles as area lights, and then L_e is left out of L so that it is counted once),
// E_indirect = sample_irradiance() (SVO mode) at the hit with the previous iteration's probes. Probes hold
// no punctual light (and, with emissive_as_lights, no emitted light) themselves: runtimes add
// direct_irradiance per pixel, and E_direct + sample_irradiance is a pixel's total irradiance.
//
// Units: W/m^2 of irradiance for emission in W/(m^2 sr) and intensities in W/sr (candela) or W/m^2 (lux).
// Deterministic for any thread count.
#pragma once

#include <cstddef>

#include <glm/vec3.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::lighting {

struct LightingSettings {
  bool enabled = true;       // the bake runs bake_lighting (false: probes keep zero irradiance)
  int rays = 256;            // Fibonacci rays per probe over the full sphere, 1..65536
  float tolerance = 1e-4f;   // stop when the estimated relative error of every probe's DC term is below
  int max_iterations = 5000; // at least 1
  bool accelerate = true;    // geometric-series extrapolation once the contraction rate is steady
  // Emissive triangles as area lights: direct_irradiance() adds their light (exact unoccluded irradiance
  // of fixed sub-triangles, one shadow ray each) and probes leave out the emission their rays see, so
  // that it is counted once. false: probes carry the emitters' light like any other surface's.
  bool emissive_as_lights = true;
  int emitter_samples = 64; // sub-triangle budget per lookup, shared by emitter power (>= 1)
  int threads = 0;          // 0 = all cores (bake::bake passes BakeSettings::threads)
};

// Throws Error(usage) naming the setting when one is out of range.
void check_lighting_settings(const LightingSettings& settings);

struct LightingReport {
  int probes = 0;                  // live probes lit
  std::size_t rays = 0;            // probe rays traced (probes * rays)
  std::size_t backface_hits = 0;   // rays that ended inside a solid (back of a single-sided surface)
  std::size_t misses = 0;          // rays that left the scene (sky)
  std::size_t indirect_misses = 0; // front hits whose SVO lookup found no probe (they get no E_indirect)
  int iterations = 0;              // Jacobi sweeps (sweep 1 = emission + direct light, one bounce each more)
  int extrapolations = 0;          // accelerated steps kept among them
  int rejected_extrapolations = 0; // steps undone because the sweep after them changed more than the one
                                   // before (docs/LIGHTING.md "Convergence"); acceleration then stops
  float change = 0.0f;             // max relative change of any probe's DC term in the last sweep
  float rate = 0.0f;               // estimated contraction rate per sweep (0 when unknown)
  float estimated_error = 0.0f;    // change * rate / (1 - rate): distance to the fixed point, relative;
                                   // -1 while the rate is unknown or >= 1
  bool converged = false;
  // Monte Carlo noise of the probes: the standard error of a probe's mean ray radiance over that mean
  // (median and 95th percentile over the lit probes). It falls as 1 / sqrt(rays); a small bright patch (sun
  // through a window) raises it, and above a few per cent it shows as blotches and stops the error falling
  // as probes are added (docs/results/lookup.md, "Convergence").
  float noise_median = 0.0f;
  float noise_p95 = 0.0f;
  double trace_seconds = 0.0; // rays, shadow rays and SVO lookups of the hits
  double iterate_seconds = 0.0;
  double seconds = 0.0; // total
};

// Lights every probe with link != 0 (volume.svo_nodes must be built; without an SVO no hit gets
// E_indirect). Throws Error(usage) for bad settings, Error(input) when a value overflows to Inf/NaN
// (e.g. emission or intensity beyond 32-bit float range) - nothing is clamped.
LightingReport bake_lighting(const scene::Scene& scene, const scene::RayScene& rays, formats::ProbeVolume& volume,
                             const LightingSettings& settings);

// Irradiance (W/m^2) at a surface point with unit `normal` from the scene's KHR_lights_punctual lights:
// point/spot I cos / r^2 with the glTF range window clamp(1 - (r/range)^4, 0, 1) when range > 0, spot cone
// falloff per the KHR_lights_punctual spec; directional I cos. A shadow ray starts 1e-4 * scene size
// along the normal. A light exactly at the point contributes 0. With settings.emissive_as_lights, plus
// the emissive triangles (double-sided ones from both sides, single-sided ones only in front of them;
// none at a point within the shadow offset of an emitter's plane, i.e. on the emitter itself):
// fixed sub-triangles (settings.emitter_samples shared by power), each its exact
// unoccluded irradiance (Lambert's formula, clipped to the hemisphere) times one shadow ray
// (docs/LIGHTING.md). Must be called with the settings the volume was baked with. Builds the patch list
// per call (O(triangles)); the bake builds it once.
glm::vec3 direct_irradiance(const scene::Scene& scene, const scene::RayScene& rays, glm::vec3 position,
                            glm::vec3 normal, const LightingSettings& settings = {});

} // namespace probebake::lighting
