// Structs and constants of the runtime's own compute passes (not stored in .probes files), shared by C++
// and GLSL like gpu_types.h: std430, explicit padding, static_assert on sizes and offsets (C++ side).
#ifndef PROBEBAKE_RUNTIME_TYPES_H
#define PROBEBAKE_RUNTIME_TYPES_H

#include "probebake/gpu_types.h"

PB_GPU_BEGIN

// Threads per workgroup of the sampling pass (one query per thread).
PB_CONSTANT(uint, RUNTIME_WORKGROUP_SIZE, 256u);

// ---- Probe index build (octree thesis §3.2.3), three dispatches over blocks of the probe buffer ---------
// Each thread handles PROBE_INDEX_PER_THREAD consecutive elements serially, and the workgroup scans the
// per-thread sums: few barriers per element (barriers are costly on CPU implementations such as lavapipe).
// A block is PROBE_INDEX_BLOCK probes. Scratch buffer: uint[block_count], per-block counts of allocated
// probes, turned in place into exclusive offsets by the scan dispatch (one workgroup, PROBE_INDEX_THREADS
// blocks per step).
PB_CONSTANT(uint, PROBE_INDEX_THREADS, 128u);
PB_CONSTANT(uint, PROBE_INDEX_PER_THREAD, 8u);
PB_CONSTANT(uint, PROBE_INDEX_BLOCK, 1024u); // PROBE_INDEX_THREADS * PROBE_INDEX_PER_THREAD
struct ProbeIndexPush {
  uint probe_capacity; // offset 0: elements in the probe buffer
  uint block_count;    // offset 4: ceil(probe_capacity / PROBE_INDEX_BLOCK)
  uint pad0;           // offset 8
  uint pad1;           // offset 12
};                     // size 16

// Written by the scan dispatch, copied back to the host after each frame.
struct RuntimeCounters {
  int live_probes; // offset  0: allocated probes (link != 0) found by the last probe index build
  int pad0;        // offset  4
  int pad1;        // offset  8
  int pad2;        // offset 12
};                 // size 16

// ---- Irradiance sampling pass (sample_irradiance.comp) ----------------------------------------------------
struct SampleQuery {
  vec3 position; // offset  0: world space, metres
  float pad0;    // offset 12
  vec3 normal;   // offset 16: unit surface normal
  float pad1;    // offset 28
};               // size 32

struct SampleResult {
  vec3 irradiance; // offset  0: W/m^2, as sample_irradiance (bake/include/probebake/probe_index/lookup.h)
  int probes_used; // offset 12: distinct probes of the blend (at most 32), 0 = miss; | SAMPLE_RESULT_NOT_LIT when streaming
};                 //   left one of them out of the light update (its irradiance is kept, not updated)
PB_CONSTANT(int, SAMPLE_RESULT_NOT_LIT, 256);

struct SamplePush {
  uint count;      // offset 0: queries in this dispatch
  uint streaming;  // offset 4: 1 = flag results whose probes have no record slot (SAMPLE_BINDING_RECORD_SLOTS)
  uint code_bands; // offset 8: 0 = the probes' float irradiance; 1 or 2 = the compact codes (l1, l2) and points
  uint pad0;       // offset 12
};                 // size 16

// ---- Compact probe codes (probe_encode.comp): every probe slot's point and code, for the lookups --------
// A point is vec4(position, 1) for an allocated probe and vec4(0) for a free slot; a code is code_bands
// uvec4 blocks (probebake/sh_code.h), zero for a free slot.
struct ProbeCodePush {
  uint probe_capacity; // offset 0: probe slots
  uint code_bands;     // offset 4: 1 (l1) or 2 (l2)
  uint pad0;           // offset 8
  uint pad1;           // offset 12
};                     // size 16

// ---- Light update (octree thesis §3.2.2), light_trace.comp / light_gather.comp / light_resolve.comp -------
// One workgroup per probe slot for trace and gather (threads over the probe's rays), one thread per probe
// for resolve. docs/RUNTIME_INTERNALS.md describes the states and buffers.
PB_CONSTANT(uint, LIGHT_WORKGROUP_SIZE, 64u);
// light_relight: one workgroup per probe too, but 256 threads (one record each at 256 rays): its shadow rays
// are the frame's longest chain, and a few hundred probes do not fill a large GPU (latency, not throughput).
PB_CONSTANT(uint, RELIGHT_WORKGROUP_SIZE, 256u);
PB_CONSTANT(int, LIGHT_RECORD_MISS, 0);     // the ray left the scene: the sky's radiance in its direction
PB_CONSTANT(int, LIGHT_RECORD_BACKFACE, 1); // the back of a single-sided triangle (inside geometry): no light
PB_CONSTANT(int, LIGHT_RECORD_FRONT, 2);    // a front face or a double-sided back: relit every frame

// One lighting ray of one probe, written by L1 (light_trace) and relit by L2 (light_gather) every frame:
//   L = base + reflect * (E_punctual(position, normal) + E_probes(position, normal)).
// E_punctual (one shadow ray per light) is cached in the record: L1 computes it, light_relight updates it
// only where a light changed or an object moved (RelightChanges), so a frame without changes costs no
// shadow ray whatever the number of lights. Records of probe p are records[p * rays, (p + 1) * rays).
struct LightRecord {
  vec3 position;    // offset  0: the hit point (front hits)
  int kind;         // offset 12: LIGHT_RECORD_*
  vec3 normal;      // offset 16: unit normal of the side the ray hit (front records); the ray's direction (miss)
  float punctual_r; // offset 28: E_punctual(position, normal), cached (front hits), else 0
  vec3 base; // offset 32: the sky's radiance (miss, light_sky); emitted + albedo / pi * emitter irradiance (front hit)
  float punctual_g; // offset 44
  vec3 reflect;     // offset 48: albedo / pi (front hits), else 0
  float punctual_b; // offset 60
};                  // size 64

// How the cached E_punctual of the records changes this frame (light_relight.comp): per light the host
// changed, its record before and after (an added or removed light is a zero-intensity record on the other
// side); a record in reach of either (inside its range, or anywhere without range) gets
// E += E_after - E_before, two shadow rays whatever the number of lights. `everything`: recompute every
// front record's whole sum instead (an object moved, more changes than RELIGHT_MAX_CHANGES).
// A light that moves frame after frame costs one shadow ray: with a single change, each front record's
// E_after is also kept in the tracked punctual buffer (a vec3 per record, LIGHT_BINDING_TRACKED_PUNCTUAL),
// and when the same light changes again, that value is its E_before.
PB_CONSTANT(uint, RELIGHT_MAX_CHANGES, 16u);
struct LightChange {
  PunctualLight before; // offset   0
  PunctualLight after;  // offset  64
};                      // size 128
// The world boxes swept by objects that moved this frame (each the union of an object's old and new box;
// more are merged into fewer). Without the memory update, light_mark_moved flags for re-tracing the probes
// whose lighting or lattice rays cross one, the others keep their records. With or without it, the relight
// recomputes only the punctual sums whose shadow ray to a light may cross one: the (box, light) pairs whose
// light reaches into the box (ShadowPair); a light out of reach of every box casts no changed shadow.
PB_CONSTANT(uint, RELIGHT_MAX_MOVED_BOXES, 64u);
PB_CONSTANT(uint, RELIGHT_MAX_SHADOW_PAIRS, 4096u); // more: every record's whole sum, as before the pairs
struct ShadowPair {
  uint box;   // offset 0: RelightChanges.boxes
  uint light; // offset 4: the punctual light
};            // size 8
struct MovedBox {
  vec3 lower; // offset  0
  float pad0; // offset 12
  vec3 upper; // offset 16
  float pad1; // offset 28
};            // size 32
struct RelightChanges {
  uint count;        // offset  0: changes in use
  uint everything;   // offset  4: 1 = recompute every front record's E_punctual
  uint reuse_before; // offset  8: 1 = changes[0].before's E at each record is in the tracked buffer
  uint track_after;  // offset 12: 1 = write changes[0].after's E at each front record to the tracked buffer
  LightChange changes[RELIGHT_MAX_CHANGES]; // offset 16
  uint moved_boxes;                         // offset 16 + 128 * RELIGHT_MAX_CHANGES: boxes in use
  uint shadows_only; // 1 = `everything` because objects moved (no light changed): only the records whose
                     //   shadow ray of a pair's light meets the pair's box are recomputed
  uint shadow_pairs; // pairs in use
  uint pad0;
  MovedBox boxes[RELIGHT_MAX_MOVED_BOXES];
  ShadowPair pairs[RELIGHT_MAX_SHADOW_PAIRS];
}; // size 32 + 128 * RELIGHT_MAX_CHANGES + 32 * RELIGHT_MAX_MOVED_BOXES + 8 * RELIGHT_MAX_SHADOW_PAIRS
// One per emitter (EmitterPatch.emitter), after RelightChanges in its buffer: the host's strength of the emitter
// (FrameInputs::emitters), by which light_trace and light_emitters scale its patches' light.
struct EmitterScale {
  vec3 scale; // offset  0: 1 as baked
  float pad0; // offset 12
};            // size 16

// Per probe slot flags (LIGHT_BINDING_TRACE_FLAGS): trace the slot's records in the next light_trace (a new or
// re-measured probe), or its cached punctual irradiance missed a light change while the probe was outside
// the gather window (light_relight recomputes its whole sums when the window reaches it). light_trace clears both.
PB_CONSTANT(uint, TRACE_FLAG_RETRACE, 1u);
PB_CONSTANT(uint, TRACE_FLAG_STALE_PUNCTUAL, 2u);
// Streaming: set by the chunks of the trace under way that saw a ray (or a shadow ray) cross a cell that is
// out before it hit anything (bvh_trace.glsl, PROBEBAKE_NULL_LEAF); the last chunk then marks the probe's
// record slot RECORD_SLOT_UNRESOLVED (bindings.h). light_trace retraces such probes whose place in the light
// list lies in the push's retry window (the host moves the window over the list after cells arrive).
PB_CONSTANT(uint, TRACE_FLAG_UNRESOLVED_NOW, 4u);

// Which probes light_trace_list lists for light_trace (LightPush::trace_mode).
PB_CONSTANT(uint, LIGHT_TRACE_FLAGGED, 0u);   // the flagged (TRACE_FLAG_RETRACE) and retried ones
PB_CONSTANT(uint, LIGHT_TRACE_EVERY, 1u);     // every live probe with records: the load trace at once
PB_CONSTANT(uint, LIGHT_TRACE_UNFLAGGED, 2u); // every live one not flagged: a window of the load trace
                                              //   (FrameLimits::max_traced_probes; the flagged ones are
                                              //   listed by a LIGHT_TRACE_FLAGGED dispatch the same frame)
struct LightPush {
  uint probe_capacity;   // offset  0
  float hysteresis;      // offset  4: new = hysteresis * old + (1 - hysteresis) * gathered
  uint trace_mode;       // offset  8: light_trace_list: LIGHT_TRACE_*
  uint listed;           // offset 12: 1 = walk the light list (the leaf queue's lit entries), 0 = the slot window
  uint first_slot;       // offset 16: not listed: the window of slots [first_slot, first_slot + slot_count),
  uint slot_count;       // offset 20:   modulo probe_capacity (FrameLimits::max_gathered_probes; all by default)
  uint probes_per_page;  // offset 24: light records: slot s is in page s / probes_per_page (light_update_bindings.h)
  int tracked_light;     // offset 28: light_trace: the light whose share it also writes to the tracked
                         //   punctual buffer (RelightChanges), -1 = none
  int shadow_rays;       // offset 32: light_trace, light_relight (everything): shadow rays per record for a
                         //   whole punctual sum; 0 = one per light (exact); else lights are sampled when there
                         //   are more (FrameLimits::shadow_rays_per_record, direct_light.glsl)
  uint seed;             // offset 36: this frame's seed of the light sampling (the same frames, the same bits)
  uint indirect_records; // offset 40: 1 = a probe's records are at LIGHT_BINDING_RECORD_SLOTS[slot] (streaming)
  uint trace_lanes;      // offset 44: light_trace: threads per record, 1 or LIGHT_TRACE_LANES (below)
  uint null_leaf;        // offset 48: streaming: the child word of a cell that is out (StreamedTracing), else 0
  uint retry_first;      // offset 52: streaming: light_trace retraces the RECORD_SLOT_UNRESOLVED probes at light
  uint retry_count;      // offset 56:   list places [retry_first, retry_first + retry_count) modulo its count
  uint retry_by_slot;    // offset 60: 1 = the retry window counts probe slots modulo probe_capacity instead
                         //   (the memory update writes the list, whose places the host does not know)
  uint untraced_from;    // offset 64: slots from here on have no records yet (a load trace spread over frames,
                         //   FrameLimits::max_traced_probes): gather keeps, relight and mark skip them; with
                         //   load_ordered, the slots whose rank in the load order is from here on
  uint load_ordered;     // offset 68: 1 = the load trace follows LIGHT_BINDING_LOAD_ORDER (UploadOptions::load_focus)
  uint relight_period;   // offset 72: light_relight (the tracked light alone) and light_sky relight only slots s
  uint relight_phase;    // offset 76:   with s % relight_period == relight_phase (FrameLimits::relight_frames)
};                       // size 80

// The probes the light update lights this frame when the memory update runs: the leaf queue's L1/L2 entries
// that the light transitions processed (memory_light appends them), then the indirect dispatch sizes
// (memory_begin phase 2); with streaming and no memory update, the host's list. Followed in the buffer by
// int probes[probe_capacity], then int traced[probe_capacity]: the slots of the probes that trace this
// frame, which light_trace_list appends before light_trace.
// light_trace runs a workgroup per chunk of those alone: a frame where few trace costs few workgroups.
struct LightListHeader {
  uint groups_x;    // offset  0: VkDispatchIndirectCommand of gather: one workgroup per listed probe,
  uint groups_y;    // offset  4:   folded into y past LIGHT_LIST_MAX_GROUPS_X
  uint groups_z;    // offset  8
  uint count;       // offset 12: listed probes
  uint resolve_x;   // offset 16: VkDispatchIndirectCommand of resolve: one thread per listed probe
  uint resolve_y;   // offset 20
  uint resolve_z;   // offset 24
  uint pad0;        // offset 28
  uint trace_x;     // offset 32: VkDispatchIndirectCommand of trace: one workgroup per probe that traces (folded
  uint trace_y;     // offset 36:   into y past LIGHT_LIST_MAX_GROUPS_X) and LIGHT_TRACE_CHUNKS, raised by
  uint trace_z;     // offset 40:   light_trace_list from zero
  uint trace_count; // offset 44: probes that trace (light_trace_list)
};                  // size 48
// light_trace spreads a probe's trace over LIGHT_TRACE_CHUNKS workgroups (gl_WorkGroupID.z) and, when few
// probes trace (probes arriving with a streamed cell, new leaves, retraces around a moved object: the cost
// is one probe's latency), each record's shadow rays (emitter patches', lights') over LIGHT_TRACE_LANES
// threads. The frame that traces every probe fills the GPU anyway and takes one thread per record
// (LightPush::trace_lanes = 1), since the lanes repeat the record's ray and light choice.
// docs/results/streaming.md "Arrivals: chunks and lanes" measures both.
PB_CONSTANT(uint, LIGHT_TRACE_LANES, 8u);
PB_CONSTANT(uint, LIGHT_TRACE_CHUNKS, 32u);
// trace_flags: light_trace's chunks count their completions in the bits from here up; the last clears the word.
PB_CONSTANT(uint, TRACE_FLAG_CHUNK_ONE, 256u);
PB_CONSTANT(uint, LIGHT_LIST_MAX_GROUPS_X, 65535u); // the least maxComputeWorkGroupCount[0] Vulkan allows

// Statistics of the light update, reset every frame; trace counts are written only in frames that trace.
struct LightCounters {
  int traced_probes;     // offset  0: probes traced by L1 this frame
  int front_hits;        // offset  4: lighting rays that hit a front face (L1)
  int backface_hits;     // offset  8: ... the back of a single-sided triangle (L1)
  int misses;            // offset 12: ... nothing (L1)
  int lit_probes;        // offset 16: probes gathered by L2 this frame
  int indirect_misses;   // offset 20: front hits whose SVO lookup found no probe (L2)
  int non_finite;        // offset 24: probes whose gathered irradiance was not finite: kept their old value
  int want_split;        // offset 28: L3: the leaf rule (leaf_rule.h) says split
  int want_free;         // offset 32: L3: the leaf rule says free the probe
  int relit_records;     // offset 36: records whose cached E_punctual light_relight updated
  int reused_records;    // offset 40: of them, updated with E_before read from the tracked buffer
  int unresolved_probes; // offset 44: streaming: traces that left RECORD_SLOT_UNRESOLVED, relights that newly set it
};                       // size 48

// ---- Dynamic objects (gpu_types.h DynamicObject; docs/RUNTIME_INTERNALS.md "Moving objects: internals") ---
// The runtime's pose of one dynamic object: the host writes world_from_object (vkCmdUpdateBuffer, rows of an
// affine 3x4 matrix), object_refit.comp derives the rest, which bvh_trace.glsl reads: rays enter the object
// (object_from_world, the same t in both spaces) only where they cross its world box.
struct ObjectInstance {
  vec4 world_from_object[3]; // offset   0: rows; xyz = linear part, w = translation
  vec4 object_from_world[3]; // offset  48: rows of the inverse (object_refit)
  vec3 world_lower;          // offset  96: world box of the object box's 8 corners, padded (object_refit)
  float pad0;                // offset 108
  vec3 world_upper;          // offset 112
  float pad1;                // offset 124
};                           // size 128

struct ObjectRefitPush {
  uint objects; // offset 0: dynamic objects (one thread each)
  uint pad0;    // offset 4
  uint pad1;    // offset 8
  uint pad2;    // offset 12
};              // size 16

// One cell's block moved in the streamed tracing arena (stream_relocate.comp): its nodes and faces, read
// from the scratch copy, written at the new place with their node, face and vertex indices shifted.
struct StreamRelocatePush {
  uint from_byte; // offset  0: the block's old arena byte offset (a multiple of 96)
  uint to_byte;   // offset  4: its new arena byte offset (a multiple of 96)
  uint nodes;     // offset  8: its inner nodes (32 bytes each, first in the block)
  uint faces;     // offset 12: its faces (16 bytes each, right after the nodes)
};                // size 16

#ifdef __cplusplus
static_assert(sizeof(StreamRelocatePush) == 16);
static_assert(sizeof(ObjectInstance) == 128 && offsetof(ObjectInstance, object_from_world) == 48 &&
              offsetof(ObjectInstance, world_lower) == 96 && offsetof(ObjectInstance, world_upper) == 112);
static_assert(sizeof(ObjectRefitPush) == 16);
static_assert(PROBE_INDEX_BLOCK == PROBE_INDEX_THREADS * PROBE_INDEX_PER_THREAD);
// light_trace.comp: whole rays per workgroup; the chunks' completion count fits above the flag bits.
static_assert(LIGHT_WORKGROUP_SIZE % LIGHT_TRACE_LANES == 0 &&
              uint64_t(LIGHT_TRACE_CHUNKS) * TRACE_FLAG_CHUNK_ONE <= 0xffffffffull);
static_assert(sizeof(ProbeIndexPush) == 16 && sizeof(RuntimeCounters) == 16 && sizeof(SamplePush) == 16);
static_assert(sizeof(ProbeCodePush) == 16);
static_assert(sizeof(SampleQuery) == 32 && offsetof(SampleQuery, normal) == 16);
static_assert(sizeof(SampleResult) == 16 && offsetof(SampleResult, probes_used) == 12);
static_assert(sizeof(LightRecord) == 64 && offsetof(LightRecord, base) == 32 && offsetof(LightRecord, reflect) == 48 &&
              offsetof(LightRecord, punctual_r) == 28 && offsetof(LightRecord, punctual_g) == 44 &&
              offsetof(LightRecord, punctual_b) == 60);
static_assert(sizeof(LightListHeader) == 48 && offsetof(LightListHeader, resolve_x) == 16 &&
              offsetof(LightListHeader, trace_x) == 32 && offsetof(LightListHeader, trace_count) == 44);
static_assert(sizeof(LightPush) == 80 && offsetof(LightPush, load_ordered) == 68 &&
              offsetof(LightPush, relight_period) == 72 && offsetof(LightPush, relight_phase) == 76 &&
              offsetof(LightPush, retry_by_slot) == 60 && offsetof(LightPush, untraced_from) == 64 &&
              offsetof(LightPush, null_leaf) == 48 && offsetof(LightPush, retry_count) == 56 &&
              offsetof(LightPush, shadow_rays) == 32 && sizeof(LightCounters) == 48 &&
              offsetof(LightCounters, relit_records) == 36);
static_assert(sizeof(LightChange) == 128 && offsetof(LightChange, after) == 64);
static_assert(sizeof(RelightChanges) ==
                  32 + 128 * RELIGHT_MAX_CHANGES + 32 * RELIGHT_MAX_MOVED_BOXES + 8 * RELIGHT_MAX_SHADOW_PAIRS &&
              offsetof(RelightChanges, pairs) == 32 + 128 * RELIGHT_MAX_CHANGES + 32 * RELIGHT_MAX_MOVED_BOXES &&
              offsetof(RelightChanges, shadow_pairs) == 24 + 128 * RELIGHT_MAX_CHANGES &&
              offsetof(RelightChanges, changes) == 16 &&
              offsetof(RelightChanges, moved_boxes) == 16 + 128 * RELIGHT_MAX_CHANGES &&
              offsetof(RelightChanges, boxes) == 32 + 128 * RELIGHT_MAX_CHANGES);
static_assert(sizeof(MovedBox) == 32 && offsetof(MovedBox, upper) == 16);
static_assert(sizeof(ShadowPair) == 8 && offsetof(ShadowPair, light) == 4);
// The EmitterScale array follows RelightChanges in its buffer at std430's 16-byte alignment.
static_assert(sizeof(EmitterScale) == 16 && sizeof(RelightChanges) % 16 == 0);
#endif
PB_GPU_END

#endif // PROBEBAKE_RUNTIME_TYPES_H
