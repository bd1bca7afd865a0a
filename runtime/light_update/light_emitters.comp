// Light update: the host changed emitter strengths (FrameInputs::emitters), so every front record adds reflect times
// the light of the patches whose emitter changed, at the change of its scale (EmitterScale.change): the record then
// holds what light_trace traces with the new strengths (to rounding), and the bounces converge from there. One
// workgroup per probe slot with records, one thread per record, one shadow ray per changed patch that can light it.
// Front records keep their bases otherwise; the scales never make a base negative.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "light_update/light_bindings.glsl"
#include "probebake/direct_light.glsl"
#include "probebake/dispatch.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

vec3 changed_emitter_irradiance(vec3 p, vec3 n) {
  const vec3 origin = p + n * probebake_lighting.shadow_offset;
  vec3 e = vec3(0.0);
  for (int i = 0; i < probebake_lighting.emitter_patches; ++i) {
    const vec3 change = emitter_scales[probebake_emitter_patches[i].emitter].change;
    if (change != vec3(0.0)) e += change * probebake_visible_patch_irradiance(i, p, n, origin);
  }
  return e;
}

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || light_slot_idle(slot) || light_slot_untraced(slot)) return; // uniform
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    LightRecord rec = light_record(slot, uint(r));
    if (rec.kind != LIGHT_RECORD_FRONT) continue;
    const vec3 change = changed_emitter_irradiance(rec.position, rec.normal);
    if (change == vec3(0.0)) continue;
    rec.base = max(rec.base + rec.reflect * change, vec3(0.0));
    set_light_record(slot, uint(r), rec);
  }
}
