// Light update: the cached punctual irradiance of the records (LightRecord.punctual_*) brought up to date
// after the host changed lights, one workgroup per live probe slot (every slot, whatever the gather window
// or the light list: a stale record would stay stale). Per changed light, a front record in reach of its
// record before or after the change gets E += E_after - E_before: two shadow rays per changed light instead of
// one per light. Outside the reach of both (beyond the range) the light gave nothing and still gives
// nothing, exactly, so the record is left alone. With `everything` (an object moved: a shadow may fall
// anywhere) every front record's sum is recomputed as light_trace computes it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

shared uint relit;

// The record's E_punctual after this frame's changes; false when none reaches it.
bool updated_punctual(LightRecord rec, out vec3 e) {
  e = vec3(0.0);
  if (relight_changes.everything != 0u) {
    e = probebake_punctual_irradiance(rec.position, rec.normal);
    return true;
  }
  vec3 delta = vec3(0.0);
  bool reached = false;
  const uint count = min(relight_changes.count, RELIGHT_MAX_CHANGES);
  for (uint c = 0u; c < count; ++c) {
    const PunctualLight before = relight_changes.changes[c].before, after = relight_changes.changes[c].after;
    const bool was = probebake_light_reaches(before, rec.position), is = probebake_light_reaches(after, rec.position);
    if (was) delta -= probebake_light_irradiance_of(before, rec.position, rec.normal);
    if (is) delta += probebake_light_irradiance_of(after, rec.position, rec.normal);
    reached = reached || was || is;
  }
  // The difference of two sums rounds: clamped at zero (removing a light leaves rounding noise, never less).
  e = max(light_record_punctual(rec) + delta, vec3(0.0));
  return reached;
}

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || probebake_probes[slot].link == 0) return; // uniform per workgroup
  if (gl_LocalInvocationIndex == 0) relit = 0u;
  barrier();
  const int rays = probebake_lighting.rays;
  uint count = 0u;
  for (int r = int(gl_LocalInvocationIndex); r < rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    LightRecord rec = light_record(slot, uint(r));
    vec3 e;
    if (rec.kind != LIGHT_RECORD_FRONT || !updated_punctual(rec, e)) continue;
    light_record_set_punctual(rec, e);
    set_light_record(slot, uint(r), rec);
    ++count;
  }
  atomicAdd(relit, count);
  barrier();
  if (gl_LocalInvocationIndex == 0 && relit > 0u) atomicAdd(light_counters.relit_records, int(relit));
}
