// Light update: the cached punctual irradiance of the records (LightRecord.punctual_*) brought up to date
// after the host changed lights, one workgroup per live probe slot. Probes in this frame's gather window
// (all of them without a gather budget, and with the light list) are brought up to date now; the others
// only note that a change reached them (TRACE_FLAG_STALE_PUNCTUAL) and get whole sums when the window
// reaches them, so the pass's shadow rays follow the gather budget. Per changed light, a front record in reach of its
// record before or after the change gets E += E_after - E_before: two shadow rays per changed light instead of
// one per light. Outside the reach of both (beyond the range) the light gave nothing and still gives
// nothing, exactly, so the record is left alone. A light that changes frame after frame (one change per
// frame) reads its E_before from the tracked buffer, where the last frame (or light_trace) left its E_after:
// one shadow ray. With `everything` (an object moved: a shadow may fall anywhere) every front record's sum
// is recomputed as light_trace computes it (lights sampled past push.shadow_rays). A change of one light
// replaces that light's exact share in a sampled sum: E - E_before + E_after stays an unbiased estimate. A
// record that several changes reach gets its whole sum instead where that casts fewer rays.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

shared uint relit, reused;

// Several changes reach the record and their differences (two shadow rays each) would cost more rays than its
// whole sum (one per light, or push.shadow_rays when lights are sampled). Never with one change: the tracked
// light's bookkeeping needs the difference path.
bool whole_sum_is_cheaper(LightRecord rec, uint count) {
  if (count < 2u) return false;
  const int lights = probebake_lighting.lights;
  const int whole = push.shadow_rays > 0 ? min(push.shadow_rays, lights) : lights;
  int reaching = 0;
  for (uint c = 0u; c < count; ++c)
    if (probebake_light_reaches(relight_changes.changes[c].before, rec.position) ||
        probebake_light_reaches(relight_changes.changes[c].after, rec.position)) ++reaching;
  return reaching >= 2 && 2 * reaching > whole;
}

// The record's E_punctual after this frame's changes; false when none reaches it. `from_tracked`: E_before
// of the single change came from the tracked buffer.
bool updated_punctual(uint slot, uint ray, LightRecord rec, out vec3 e, out bool from_tracked) {
  e = vec3(0.0);
  from_tracked = false;
  const uint count = min(relight_changes.count, RELIGHT_MAX_CHANGES);
  if (relight_changes.everything != 0u || whole_sum_is_cheaper(rec, count)) {
    vec3 unused;
    e = probebake_punctual_irradiance_budgeted(rec.position, rec.normal, push.shadow_rays, -1,
                                               probebake_record_seed(push.seed, slot, ray), unused);
    return true;
  }
  vec3 delta = vec3(0.0);
  bool reached = false;
  for (uint c = 0u; c < count; ++c) {
    const PunctualLight before = relight_changes.changes[c].before, after = relight_changes.changes[c].after;
    const bool was = probebake_light_reaches(before, rec.position), is = probebake_light_reaches(after, rec.position);
    const bool tracked = c == 0u && relight_changes.reuse_before != 0u;
    // The tracked value is 0 where the light did not reach (track_after wrote every front record).
    const vec3 e_before = tracked ? tracked_punctual_at(slot, ray)
                                  : (was ? probebake_light_irradiance_of(before, rec.position, rec.normal) : vec3(0.0));
    const vec3 e_after = is ? probebake_light_irradiance_of(after, rec.position, rec.normal) : vec3(0.0);
    if (c == 0u && relight_changes.track_after != 0u) set_tracked_punctual(slot, ray, e_after);
    delta += e_after - e_before;
    from_tracked = from_tracked || (tracked && (was || is));
    reached = reached || was || is;
  }
  // The difference of two sums rounds: clamped at zero (removing a light leaves rounding noise, never less).
  e = max(light_record_punctual(rec) + delta, vec3(0.0));
  return reached;
}

// The record's whole sum after it missed changes outside the gather window, with the tracked light's share
// written to the tracked buffer as light_trace writes it (later changes of that light read it as E_before).
vec3 caught_up_punctual(uint slot, uint ray, LightRecord rec) {
  vec3 tracked;
  const vec3 e = probebake_punctual_irradiance_budgeted(rec.position, rec.normal, push.shadow_rays, push.tracked_light,
                                                        probebake_record_seed(push.seed, slot, ray), tracked);
  if (push.tracked_light >= 0) set_tracked_punctual(slot, ray, tracked);
  return e;
}

// Whether this frame's changes reach the record (no shadow ray: ranges only).
bool changes_reach(LightRecord rec) {
  if (relight_changes.everything != 0u) return true;
  const uint count = min(relight_changes.count, RELIGHT_MAX_CHANGES);
  for (uint c = 0u; c < count; ++c)
    if (probebake_light_reaches(relight_changes.changes[c].before, rec.position) ||
        probebake_light_reaches(relight_changes.changes[c].after, rec.position)) return true;
  return false;
}

bool in_gather_window(uint slot) { return (slot + push.probe_capacity - push.first_slot) % push.probe_capacity < push.slot_count; }

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || probebake_probes[slot].link == 0) return; // uniform per workgroup
  const bool stale = (trace_flags[slot] & TRACE_FLAG_STALE_PUNCTUAL) != 0u;
  const bool changed = relight_changes.everything != 0u || relight_changes.count > 0u;
  const int rays = probebake_lighting.rays;
  if (!in_gather_window(slot)) {
    // Not gathered this frame: no shadow ray now. A probe the changes reach is marked stale and catches up
    // with whole sums when the window reaches it (FrameLimits::max_gathered_probes bounds this pass too).
    if (stale || !changed) return;
    bool reached = false;
    for (int r = int(gl_LocalInvocationIndex); r < rays && !reached; r += int(LIGHT_WORKGROUP_SIZE)) {
      const LightRecord rec = light_record(slot, uint(r));
      reached = rec.kind == LIGHT_RECORD_FRONT && changes_reach(rec);
    }
    if (reached) atomicOr(trace_flags[slot], TRACE_FLAG_STALE_PUNCTUAL);
    return;
  }
  if (!stale && !changed) return; // uniform per workgroup
  if (gl_LocalInvocationIndex == 0) {
    relit = 0u;
    reused = 0u;
  }
  barrier();
  uint count = 0u, from_tracked_count = 0u;
  for (int r = int(gl_LocalInvocationIndex); r < rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    LightRecord rec = light_record(slot, uint(r));
    if (rec.kind != LIGHT_RECORD_FRONT) continue;
    vec3 e;
    bool from_tracked = false;
    if (stale) e = caught_up_punctual(slot, uint(r), rec);
    else if (!updated_punctual(slot, uint(r), rec, e, from_tracked)) continue;
    light_record_set_punctual(rec, e);
    set_light_record(slot, uint(r), rec);
    ++count;
    if (from_tracked) ++from_tracked_count;
  }
  atomicAdd(relit, count);
  atomicAdd(reused, from_tracked_count);
  barrier();
  if (gl_LocalInvocationIndex != 0) return;
  if (stale) trace_flags[slot] &= ~TRACE_FLAG_STALE_PUNCTUAL;
  if (relit > 0u) atomicAdd(light_counters.relit_records, int(relit));
  if (reused > 0u) atomicAdd(light_counters.reused_records, int(reused));
}
