// Light update L2 (octree thesis §3.2.2, "light surfels and probe"): one workgroup per probe slot of the
// window (or listed probe). Every record is relit, L = base + reflect * (E_punctual + E_probes), E_punctual
// cached in the record (light_trace, light_relight), E_probes from the previous frame's probes through the
// SVO sampler (sample_irradiance.glsl); the radiance is projected onto L2 SH irradiance with
// Monte Carlo weight 4 pi / rays (lighting/src/iteration.cpp) and blended with the probe's old value
// by the hysteresis into next_irradiance, at the probe's record slot (the probes themselves are written by
// light_resolve, so that every probe of this frame reads last frame's values: a Jacobi sweep, deterministic). A probe whose last trace
// crossed a streamed cell that is out (RECORD_SLOT_UNRESOLVED) keeps its irradiance, and so does one that a
// load trace spread over frames has not reached (its baked irradiance is right until its records exist).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/sample_irradiance.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

shared float partial[LIGHT_WORKGROUP_SIZE][PROBE_SH_FLOATS];
shared uint indirect_misses;

const float SH_BAND[9] = float[9](SH_BAND0, SH_BAND1, SH_BAND1, SH_BAND1, SH_BAND2, SH_BAND2, SH_BAND2, SH_BAND2,
                                  SH_BAND2); // gpu_types.h's A_l per coefficient

vec3 relight(LightRecord rec) {
  if (rec.kind != LIGHT_RECORD_FRONT) return rec.base;
  const ProbebakeStencil s = probebake_svo_stencil(rec.position, rec.normal);
  if (s.probes.x < 0) atomicAdd(indirect_misses, 1u);
  const vec3 e = light_record_punctual(rec) + probebake_apply_stencil(s, rec.normal);
  return rec.base + rec.reflect * e;
}

void main() {
  const int listed = light_slot(probebake_flat_workgroup());
  if (listed < 0 || light_slot_idle(uint(listed))) return; // uniform per workgroup
  const uint slot = uint(listed);
  const uint next = uint(PROBE_SH_FLOATS) * uint(light_record_slot(slot)); // streaming: next_irradiance holds the lit probes only
  const uint t = gl_LocalInvocationIndex;
  // Its rays crossed a cell that is out, or it has no records yet: keep its light.
  if (light_slot_unresolved(slot) || light_slot_untraced(slot)) {
    if (t == 0u)
      for (int v = 0; v < PROBE_SH_FLOATS; ++v) next_irradiance[next + uint(v)] = probebake_probes[slot].irradiance_sh[v];
    return;
  }
  if (t == 0) indirect_misses = 0u;
  float acc[PROBE_SH_FLOATS];
  for (int v = 0; v < PROBE_SH_FLOATS; ++v) acc[v] = 0.0;
  const int rays = probebake_lighting.rays;
  const float weight = 4.0 * 3.14159265 / float(rays);
  barrier();
  for (int r = int(t); r < rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    const vec3 radiance = relight(light_record(slot, uint(r)));
    float y[9];
    probebake_sh_basis(probebake_ray_directions[r].xyz, y);
    for (int k = 0; k < 9; ++k) {
      const float w = y[k] * (weight * SH_BAND[k]); // the CPU's projection table, same rounding
      acc[3 * k] += radiance.r * w;
      acc[3 * k + 1] += radiance.g * w;
      acc[3 * k + 2] += radiance.b * w;
    }
  }
  for (int v = 0; v < PROBE_SH_FLOATS; ++v) partial[t][v] = acc[v];
  barrier();
  // Fixed-order tree reduction: the same sum on every run.
  for (uint stride = LIGHT_WORKGROUP_SIZE / 2u; stride > 0u; stride >>= 1u) {
    if (t < stride)
      for (int v = 0; v < PROBE_SH_FLOATS; ++v) partial[t][v] += partial[t + stride][v];
    barrier();
  }
  if (t != 0u) return;
  bool finite = true;
  float blended[PROBE_SH_FLOATS];
  for (int v = 0; v < PROBE_SH_FLOATS; ++v) {
    const float old = probebake_probes[slot].irradiance_sh[v];
    blended[v] = push.hysteresis * old + (1.0 - push.hysteresis) * partial[0][v];
    finite = finite && !isnan(blended[v]) && !isinf(blended[v]);
  }
  // No NaN or Inf leaves the pass: a probe that would overflow keeps its value and is counted.
  for (int v = 0; v < PROBE_SH_FLOATS; ++v) next_irradiance[next + uint(v)] = finite ? blended[v] : probebake_probes[slot].irradiance_sh[v];
  atomicAdd(light_counters.lit_probes, 1);
  atomicAdd(light_counters.indirect_misses, int(indirect_misses));
  if (!finite) atomicAdd(light_counters.non_finite, 1);
}
