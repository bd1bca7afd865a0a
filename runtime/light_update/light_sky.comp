// Light update: the host changed the sky (FrameInputs::sky), so every record of a ray that left the scene takes
// the new sky's radiance in its direction (kept in the record's normal by light_trace). One workgroup per probe
// slot, every slot with records, or this frame's window of them (FrameLimits::relight_frames: the others in the
// next frames); the gather after it relights the probes from there and the bounces converge over the next frames.
// Front records keep their bases: sky light reaches surfaces through the probes.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/sky.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || light_slot_idle(slot) || light_slot_untraced(slot)) return; // uniform
  if (push.relight_period > 1u && slot % push.relight_period != push.relight_phase) return; // relight_frames
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    LightRecord rec = light_record(slot, uint(r));
    if (rec.kind != LIGHT_RECORD_MISS) continue;
    rec.base = probebake_sky_radiance(rec.normal);
    set_light_record(slot, uint(r), rec);
  }
}
