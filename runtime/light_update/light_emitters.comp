// Light update: the host changed emitter strengths (FrameInputs::emitters), so every front record's emitter light
// is summed again at the new strengths (base = albedo / pi x the scaled patches' irradiance, as light_trace makes
// it with emissive_as_lights): one shadow ray per patch that can light the record and is not switched off. Per probe
// slot with records, or this frame's window of them (FrameLimits::relight_frames: the others in the next frames,
// from the strengths of then), one workgroup per LIGHT_WORKGROUP_SIZE records (gl_WorkGroupID.z), one record a
// thread; the bounces converge from there over the next frames.
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
  const int step = int(LIGHT_WORKGROUP_SIZE * gl_NumWorkGroups.z);
  for (int r = int(gl_LocalInvocationIndex + LIGHT_WORKGROUP_SIZE * gl_WorkGroupID.z); r < probebake_lighting.rays;
       r += step) {
    LightRecord rec = light_record(slot, uint(r));
    if (rec.kind != LIGHT_RECORD_FRONT) continue;
    rec.base = rec.reflect * probebake_emitter_irradiance_share(rec.position, rec.normal, 0u, 1u);
    set_light_record(slot, uint(r), rec);
  }
}
