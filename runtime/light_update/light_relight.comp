// Light update: the cached punctual irradiance of the records (LightRecord.punctual_*) brought up to date
// after the host changed lights, one workgroup per probe slot of the window it is given: every slot, or, in
// frames whose whole sums the gather budget rations (light_update_pass.cpp), the gather window, after
// light_mark_stale marked the probes outside it that the changes reach; a stale probe in the window gets its
// whole sums. Per changed light, a front record in reach of its
// record before or after the change gets E += E_after - E_before: two shadow rays per changed light instead of
// one per light. Outside the reach of both (beyond the range) the light gave nothing and still gives
// nothing, exactly, so the record is left alone. A light that changes frame after frame (one change per
// frame) reads its E_before from the tracked buffer, where the last frame (or light_trace) left its E_after:
// one shadow ray, and with FrameLimits::relight_frames only in every relight_period-th slot. With `everything`
// (more than RELIGHT_MAX_CHANGES changes, or an object moved) every front record's sum is recomputed as
// light_trace computes it (lights sampled past push.shadow_rays); when only objects moved (`shadows_only`),
// only the records whose shadow ray to a light may cross a moved box are (shadow_may_have_moved). A change of
// one light replaces that light's exact share in a sampled sum: E - E_before + E_after stays an unbiased estimate. A
// record that several changes reach gets its whole sum instead where that casts fewer rays. Streaming: a
// shadow ray that crosses a cell that is out leaves the probe RECORD_SLOT_UNRESOLVED, as in light_trace (the
// gather keeps its irradiance until a retry traces its records afresh).
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_NULL_LEAF push.null_leaf // streaming: shadow rays that cross a cell that is out (bvh_trace.glsl)
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"

layout(local_size_x = RELIGHT_WORKGROUP_SIZE) in;

shared uint relit, reused, unresolved_records;

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

// An object moved and no light changed (RelightChanges.shadows_only): the record's punctual sum can change only
// where the shadow ray of a light that reaches it meets a moved box, for the pairs whose light reaches into
// that box. Conservative: padded boxes, whatever the light's unshadowed term.
bool shadow_may_have_moved(LightRecord rec) {
  const vec3 origin = rec.position + rec.normal * probebake_lighting.shadow_offset; // as the shadow ray
  const uint pairs = min(relight_changes.shadow_pairs, RELIGHT_MAX_SHADOW_PAIRS);
  for (uint i = 0u; i < pairs; ++i) {
    const ShadowPair pair = relight_changes.pairs[i];
    if (pair.light >= uint(probebake_lighting.lights) || pair.box >= RELIGHT_MAX_MOVED_BOXES) continue;
    const PunctualLight light = probebake_lights[pair.light];
    if (!probebake_light_reaches(light, rec.position)) continue;
    const bool directional = light.type == LIGHT_DIRECTIONAL;
    const vec3 dir = directional ? -light.direction : light.position - origin; // t in [0, 1] to a point light
    if (segment_meets_box(origin, dir, directional ? 3.0e38 : 1.0, relight_changes.boxes[pair.box])) return true;
  }
  return false;
}

// The record's E_punctual after this frame's changes; false when none reaches it. `from_tracked`: E_before
// of the single change came from the tracked buffer. A stale record (it missed changes outside the gather
// window) takes its whole sum; no light is tracked while any record may be stale (light_update_pass.cpp).
// The whole sum is called with no tracked light (a constant): with the tracked share kept here too, the
// pass ran 2x slower on an H100 (registers), in every frame, whichever path a frame took.
bool updated_punctual(uint slot, uint ray, LightRecord rec, bool stale, out vec3 e, out bool from_tracked) {
  e = vec3(0.0);
  from_tracked = false;
  const uint count = min(relight_changes.count, RELIGHT_MAX_CHANGES);
  if (stale || relight_changes.everything != 0u || whole_sum_is_cheaper(rec, count)) {
    if (!stale && relight_changes.shadows_only != 0u && !shadow_may_have_moved(rec)) return false; // unchanged
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

void main() {
  // One workgroup per slot of this frame's window (push.first_slot on, modulo the capacity).
  const uint group = probebake_flat_workgroup();
  const uint slot = (push.first_slot + group) % max(push.probe_capacity, 1u);
  if (group >= push.slot_count || light_slot_idle(slot) || light_slot_untraced(slot)) return; // uniform per workgroup
  const bool stale = (trace_flags[slot] & TRACE_FLAG_STALE_PUNCTUAL) != 0u;
  if (!stale && relight_changes.everything == 0u && relight_changes.count == 0u) return; // uniform
  // FrameLimits::relight_frames: the tracked light changing alone relights this frame's window of slots; the others
  // catch up in the next frames, from the tracked value they were last given (E_before), so no change is lost.
  const bool tracked_alone = relight_changes.everything == 0u && relight_changes.count == 1u &&
                             relight_changes.reuse_before != 0u;
  if (!stale && tracked_alone && push.relight_period > 1u && slot % push.relight_period != push.relight_phase) return;
  if (gl_LocalInvocationIndex == 0) {
    relit = 0u;
    reused = 0u;
    unresolved_records = 0u;
  }
  barrier();
  const int rays = probebake_lighting.rays;
  uint count = 0u, from_tracked_count = 0u, unresolved_count = 0u;
  for (int r = int(gl_LocalInvocationIndex); r < rays; r += int(RELIGHT_WORKGROUP_SIZE)) {
    LightRecord rec = light_record(slot, uint(r));
    vec3 e;
    bool from_tracked;
    probebake_ray_unresolved = false;
    if (rec.kind != LIGHT_RECORD_FRONT || !updated_punctual(slot, uint(r), rec, stale, e, from_tracked)) continue;
    if (probebake_ray_unresolved) ++unresolved_count;
    light_record_set_punctual(rec, e);
    set_light_record(slot, uint(r), rec);
    ++count;
    if (from_tracked) ++from_tracked_count;
  }
  atomicAdd(relit, count);
  atomicAdd(reused, from_tracked_count);
  atomicAdd(unresolved_records, unresolved_count);
  barrier();
  if (gl_LocalInvocationIndex != 0) return;
  if (stale) atomicAnd(trace_flags[slot], ~TRACE_FLAG_STALE_PUNCTUAL);
  if (unresolved_records > 0u && !light_set_unresolved(slot, true)) atomicAdd(light_counters.unresolved_probes, 1);
  if (relit > 0u) atomicAdd(light_counters.relit_records, int(relit));
  if (reused > 0u) atomicAdd(light_counters.reused_records, int(reused));
}
