// The light update kernels' bindings (light_trace, light_gather, light_resolve, ...): the volume set
// (volume_bindings.glsl) and the pass's own buffers in set 1 (light_update_bindings.h). The gather samples
// the probes through sample_irradiance.glsl, the same code a game uses.
// Define PROBEBAKE_WRITES_PROBES before including to write the probe buffer, PROBEBAKE_LIGHT_LIST_WRITABLE
// to write the light list.
#ifndef PROBEBAKE_LIGHT_BINDINGS_GLSL
#define PROBEBAKE_LIGHT_BINDINGS_GLSL

#include "probebake/volume_bindings.glsl"
#include "light_update/light_update_bindings.h"

#ifdef PROBEBAKE_LIGHT_LIST_WRITABLE
#define PROBEBAKE_LIGHT_LIST_ACCESS
#else
#define PROBEBAKE_LIGHT_LIST_ACCESS readonly
#endif

#define PROBEBAKE_LIGHT_BUFFER(index) layout(std430, set = PASS_SET, binding = index) buffer
// clang-format off
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_RECORDS) RecordPage0 { LightRecord light_records_0[]; };
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_RECORDS + 1u) RecordPage1 { LightRecord light_records_1[]; };
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_RECORDS + 2u) RecordPage2 { LightRecord light_records_2[]; };
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_RECORDS + 3u) RecordPage3 { LightRecord light_records_3[]; };
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_NEXT_IRRADIANCE) NextIrradianceBuffer { float next_irradiance[]; }; // PROBE_SH_FLOATS per record slot
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_COUNTERS) CounterBuffer { LightCounters light_counters; };
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_TRACE_FLAGS) TraceFlagBuffer { uint trace_flags[]; };
// The listed probe slots at [0, probe_capacity), the slots that trace at [probe_capacity, 2 probe_capacity).
layout(std430, set = PASS_SET, binding = LIGHT_BINDING_LIGHT_LIST) PROBEBAKE_LIGHT_LIST_ACCESS buffer LightListBuffer {
  LightListHeader light_list_header;
  int light_list[];
};
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_TRACKED_PUNCTUAL) TrackedPunctualBuffer { float tracked_punctual[]; }; // 3 per record
layout(std430, set = PASS_SET, binding = LIGHT_BINDING_RELIGHT_CHANGES) readonly buffer RelightChangeBuffer {
  RelightChanges relight_changes;
  EmitterScale emitter_scales[]; // one per emitter (FrameInputs::emitters)
};
PROBEBAKE_LIGHT_BUFFER(LIGHT_BINDING_RECORD_SLOTS) RecordSlotBuffer { int light_record_slots[]; };
layout(std430, set = PASS_SET, binding = LIGHT_BINDING_LOAD_ORDER) readonly buffer LoadOrderBuffer { int load_order[]; };
// clang-format on
layout(push_constant) uniform Push { LightPush push; };
#define PROBEBAKE_EMITTER_SCALE(e) emitter_scales[e].scale // direct_light.glsl

// The probe slot of workgroup (or thread) `index`: the index-th slot of the window, or the light list's
// entry when the light update walks the list (push.listed); -1 past the end.
int light_slot(uint index) {
  if (push.listed == 0u) return index < push.slot_count ? int((push.first_slot + index) % push.probe_capacity) : -1;
  if (index >= light_list_header.count) return -1;
  const int slot = light_list[index];
  return slot >= 0 && uint(slot) < push.probe_capacity ? slot : -1;
}

// Where probe slot `slot` keeps its records: its own slot, or with streaming the slot the host gave it (-1:
// none, the probe is not lit), without the RECORD_SLOT_UNRESOLVED bit.
int light_record_slot(uint slot) {
  if (push.indirect_records == 0u) return int(slot);
  const int r = light_record_slots[slot];
  return r < 0 ? -1 : r & ~RECORD_SLOT_UNRESOLVED;
}

// Streaming: the probe's last trace or relight had a ray cross a cell that is out (bindings.h).
bool light_slot_unresolved(uint slot) {
  return push.indirect_records != 0u && light_record_slots[slot] >= 0 && (light_record_slots[slot] & RECORD_SLOT_UNRESOLVED) != 0;
}
// Sets or clears that bit of a probe with records; returns whether it was set before.
bool light_set_unresolved(uint slot, bool unresolved) {
  if (push.indirect_records == 0u || light_record_slots[slot] < 0) return false;
  const int before = unresolved ? atomicOr(light_record_slots[slot], RECORD_SLOT_UNRESOLVED)
                                : atomicAnd(light_record_slots[slot], ~RECORD_SLOT_UNRESOLVED);
  return (before & RECORD_SLOT_UNRESOLVED) != 0;
}

// Whether the light update skips the probe: a free slot, or a probe without records (uniform per workgroup).
bool light_slot_idle(uint slot) { return probebake_probes[slot].link == 0 || light_record_slot(slot) < 0; }

// Streaming: whether list place `place` (or, with push.retry_by_slot, probe slot `slot`) lies in the retry
// window [retry_first, retry_first + retry_count) modulo the list's count (or the slots'): a probe left
// unresolved by its last trace is traced again there.
bool in_retry_window(uint place, uint slot) {
  const uint count = push.retry_by_slot != 0u ? push.probe_capacity : light_list_header.count;
  const uint i = push.retry_by_slot != 0u ? slot : place;
  return push.retry_count != 0u && count != 0u && (i + count - push.retry_first % count) % count < push.retry_count;
}

// The place-th slot of this frame's load window [first_slot, first_slot + slot_count) of the load order: slot
// order, or nearest the load focus first (push.load_ordered); -1 past the end.
int light_load_slot(uint place) {
  const uint i = push.first_slot + place;
  if (place >= push.slot_count || i >= push.probe_capacity) return -1;
  return push.load_ordered != 0u ? load_order[i] : int(i);
}

// The probe slot that light_trace traces at list place (or window index) `place` this frame, or -1: a live
// probe with records that is flagged (TRACE_FLAG_RETRACE) or unresolved in the retry window, or by
// push.trace_mode every one, or every one not flagged (LIGHT_TRACE_*).
int light_trace_slot(uint place) {
  const int listed = push.trace_mode == LIGHT_TRACE_UNFLAGGED ? light_load_slot(place) : light_slot(place);
  if (listed < 0 || light_slot_idle(uint(listed))) return -1;
  const uint slot = uint(listed);
  const bool flagged = (trace_flags[slot] & TRACE_FLAG_RETRACE) != 0u;
  if (push.trace_mode == LIGHT_TRACE_UNFLAGGED) return flagged ? -1 : listed;
  const bool retry = light_slot_unresolved(slot) && in_retry_window(place, slot); // streaming only
  return push.trace_mode == LIGHT_TRACE_EVERY || flagged || retry ? listed : -1;
}

// A load trace spread over frames has not reached the slot yet: it has no records (push.untraced_from).
bool light_slot_untraced(uint slot) {
  const uint rank = push.load_ordered != 0u ? uint(load_order[push.probe_capacity + slot]) : slot;
  return rank >= push.untraced_from;
}

// Record `ray` of probe slot `slot` (which has records): page r / probes_per_page of its record slot r
// (uniform per workgroup: one slot each), and the index in that page. The record slot is read once.
uvec2 light_record_place(uint slot, uint ray) {
  const uint r = uint(light_record_slot(slot)), page = r / push.probes_per_page;
  return uvec2(page, (r - page * push.probes_per_page) * uint(probebake_lighting.rays) + ray);
}

LightRecord light_record(uint slot, uint ray) {
  const uvec2 place = light_record_place(slot, ray);
  const uint page = place.x, i = place.y;
  if (page == 0u) return light_records_0[i];
  if (page == 1u) return light_records_1[i];
  if (page == 2u) return light_records_2[i];
  return light_records_3[i];
}

void set_light_record(uint slot, uint ray, LightRecord rec) {
  const uvec2 place = light_record_place(slot, ray);
  const uint page = place.x, i = place.y;
  if (page == 0u) light_records_0[i] = rec;
  else if (page == 1u) light_records_1[i] = rec;
  else if (page == 2u) light_records_2[i] = rec;
  else light_records_3[i] = rec;
}

// The tracked light's E at record `ray` of `slot` (RelightChanges), unpaged: 12 bytes per record.
vec3 tracked_punctual_at(uint slot, uint ray) {
  const uint i = 3u * (uint(light_record_slot(slot)) * uint(probebake_lighting.rays) + ray);
  return vec3(tracked_punctual[i], tracked_punctual[i + 1u], tracked_punctual[i + 2u]);
}

void set_tracked_punctual(uint slot, uint ray, vec3 e) {
  const uint i = 3u * (uint(light_record_slot(slot)) * uint(probebake_lighting.rays) + ray);
  tracked_punctual[i] = e.r;
  tracked_punctual[i + 1u] = e.g;
  tracked_punctual[i + 2u] = e.b;
}

vec3 light_record_punctual(LightRecord rec) { return vec3(rec.punctual_r, rec.punctual_g, rec.punctual_b); }

void light_record_set_punctual(inout LightRecord rec, vec3 e) {
  rec.punctual_r = e.r;
  rec.punctual_g = e.g;
  rec.punctual_b = e.b;
}

// Whether origin + t dir, t in [0, t_max], meets the box padded by a relative 1e-4 (a conservative slab test:
// a zero direction component is inside its slab or not at all). light_mark_moved, light_relight.
bool segment_meets_box(vec3 origin, vec3 dir, float t_max, MovedBox box) {
  const vec3 pad = 1e-4 * (box.upper - box.lower) + vec3(1e-6);
  const vec3 lower = box.lower - pad, upper = box.upper + pad;
  float t0 = 0.0, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] == 0.0) {
      if (origin[a] < lower[a] || origin[a] > upper[a]) return false;
      continue;
    }
    const float inv = 1.0 / dir[a];
    const float near = (lower[a] - origin[a]) * inv, far = (upper[a] - origin[a]) * inv;
    t0 = max(t0, min(near, far));
    t1 = min(t1, max(near, far));
  }
  return t0 <= t1 * 1.0001 + 1e-6;
}

#endif // PROBEBAKE_LIGHT_BINDINGS_GLSL
