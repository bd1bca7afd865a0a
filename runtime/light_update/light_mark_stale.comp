// Light update, frames whose whole punctual sums the gather budget rations (light_update_pass.cpp): a live
// probe outside this frame's gather window that one of the frame's changes reaches (an object moved: all) is
// marked stale (TRACE_FLAG_STALE_PUNCTUAL); light_relight recomputes its whole sums when the window reaches
// it. No shadow ray: ranges only. A pass of its own, so that light_relight stays as small as it was.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

bool changes_reach(vec3 p) {
  if (relight_changes.everything != 0u) return true;
  const uint count = min(relight_changes.count, RELIGHT_MAX_CHANGES);
  for (uint c = 0u; c < count; ++c)
    if (probebake_light_reaches(relight_changes.changes[c].before, p) || probebake_light_reaches(relight_changes.changes[c].after, p))
      return true;
  return false;
}

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || light_slot_idle(slot)) return; // uniform per workgroup
  const bool in_window = (slot + push.probe_capacity - push.first_slot) % push.probe_capacity < push.slot_count;
  if (in_window || (trace_flags[slot] & TRACE_FLAG_STALE_PUNCTUAL) != 0u) return;
  bool reached = false;
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.rays && !reached; r += int(LIGHT_WORKGROUP_SIZE)) {
    const LightRecord rec = light_record(slot, uint(r));
    reached = rec.kind == LIGHT_RECORD_FRONT && changes_reach(rec.position);
  }
  if (reached) atomicOr(trace_flags[slot], TRACE_FLAG_STALE_PUNCTUAL);
}
