// Light update: the cached punctual irradiance of the records (LightRecord.punctual_*) made current again
// where it went stale this frame, one workgroup per live probe slot (every slot, whatever the gather window
// or the light list: a stale record would stay stale). A front record is recomputed when it lies inside one
// of the RelightRegions spheres (outside the range of a light, before and after its change, that light gave
// nothing and still gives nothing) or when `everything` is set. The same function as light_trace, so a
// relit record holds what a fresh trace would.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

shared uint relit;

bool is_stale(vec3 p) {
  if (relight_regions.everything != 0u) return true;
  const uint count = min(relight_regions.count, RELIGHT_MAX_REGIONS);
  for (uint i = 0u; i < count; ++i) {
    const vec4 sphere = relight_regions.spheres[i];
    const vec3 d = p - sphere.xyz;
    // The range window is 0 from distance == range on; a relative margin covers the rounding of both sides.
    if (dot(d, d) <= sphere.w * sphere.w * 1.0001 + 1e-12) return true;
  }
  return false;
}

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || probebake_probes[slot].link == 0) return; // uniform per workgroup
  if (gl_LocalInvocationIndex == 0) relit = 0u;
  barrier();
  const int rays = probebake_lighting.rays;
  uint count = 0u;
  for (int r = int(gl_LocalInvocationIndex); r < rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    const uint index = slot * uint(rays) + uint(r);
    LightRecord rec = light_records[index];
    if (rec.kind != LIGHT_RECORD_FRONT || !is_stale(rec.position)) continue;
    light_record_set_punctual(rec, probebake_punctual_irradiance(rec.position, rec.normal));
    light_records[index] = rec;
    ++count;
  }
  atomicAdd(relit, count);
  barrier();
  if (gl_LocalInvocationIndex == 0 && relit > 0u) atomicAdd(light_counters.relit_records, int(relit));
}
