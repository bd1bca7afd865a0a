// Light update: the host changed emitter strengths (FrameInputs::emitters), so every front record's emitter light
// is summed again at the new strengths (base = albedo / pi x the scaled patches' irradiance, as light_trace makes
// it with emissive_as_lights): one shadow ray per patch that can light the record and is not switched off. One
// workgroup per probe slot with records, or this frame's window of them (FrameLimits::relight_frames: the others in
// the next frames, from the strengths of then); the bounces converge from there over the next frames.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "light_update/light_bindings.glsl"
#include "probebake/direct_light.glsl"
#include "probebake/dispatch.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || light_slot_idle(slot) || light_slot_untraced(slot)) return; // uniform
  if (push.relight_period > 1u && slot % push.relight_period != push.relight_phase) return; // relight_frames
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    LightRecord rec = light_record(slot, uint(r));
    if (rec.kind != LIGHT_RECORD_FRONT) continue;
    rec.base = rec.reflect * probebake_emitter_irradiance_share(rec.position, rec.normal, 0u, 1u);
    set_light_record(slot, uint(r), rec);
  }
}
