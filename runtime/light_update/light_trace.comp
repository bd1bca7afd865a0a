// Light update L1 (octree thesis §3.2.2, "place surfels"): LIGHT_TRACE_CHUNKS workgroups per probe that
// traces (gl_WorkGroupID.z: chunk c takes the lighting rays r with (r / g) % chunks == c, g =
// LIGHT_WORKGROUP_SIZE / push.trace_lanes rays per workgroup; chunk 0 also the lattice), every live probe on
// the first frame, then the probes whose trace flag is set (new probes, re-measured leaves, cells that
// arrived) or that are retried: light_trace_list.comp lists them first. The last chunk to finish clears
// the flag.
//  - Hit fraction: the placement lattice (ray_directions[rays, rays + placement_rays)) traced from the
//    centre of the probe's octree node, hits counted inside the node cube (placement/src/probe_tracing.cpp);
//    octree probes only (grid probes keep the bake's value).
//  - Lighting rays: ray_directions[0, rays) from the probe to the nearest hit at any distance, each kept as
//    a LightRecord with what does not change from frame to frame (lighting/src/hit_cache.cpp) and the
//    punctual irradiance, cached until a light or an object changes (light_relight.comp).
//  Both use the bake's sides rule (glTF doubleSided): only the back of a single-sided triangle is inside
//  geometry (a back-face hit and record); the back of a double-sided one is shaded with the facing normal.
//  Streaming: when a lighting ray or one of its shadow rays crosses a cell that is out before it hits,
//  the probe's record slot is left RECORD_SLOT_UNRESOLVED (bindings.h): the gather keeps its irradiance, a
//  lookup says it is not lit, and a trace in a later frame's retry window tries again.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_WRITES_PROBES
#define PROBEBAKE_NULL_LEAF push.null_leaf // streaming: rays that cross a cell that is out (bvh_trace.glsl)
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"
#include "probebake/octree.glsl"
#include "probebake/sky.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

shared uint hits_in_cube, hits, backface_hits;
shared uint front_count, back_count, miss_count;
shared uint unresolved_records;
shared bool probe_inside_out_cell;
shared vec3 lane_emitter[LIGHT_WORKGROUP_SIZE], lane_punctual[LIGHT_WORKGROUP_SIZE], lane_tracked[LIGHT_WORKGROUP_SIZE];

void measure_hit_fraction(int probe) {
  vec3 cube_min;
  float size;
  int depth;
  octree_node_cube(probebake_probes[probe].node, cube_min, size, depth);
  precise const vec3 centre = cube_min + vec3(0.5 * size);
  uint in_cube = 0u, all_hits = 0u, backface = 0u, unresolved = 0u; // the lighting rays decide unresolved
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.placement_rays; r += int(LIGHT_WORKGROUP_SIZE))
    octree_lattice_ray(cube_min, size, centre, r, in_cube, all_hits, backface, unresolved);
  atomicAdd(hits_in_cube, in_cube);
  atomicAdd(hits, all_hits);
  atomicAdd(backface_hits, backface);
}

// The ray's hit as a record without its light (base holds the emission), counted once (lane 0). A miss keeps
// the ray's direction in `normal`, so that light_sky relights it when the host changes the sky.
LightRecord trace_hit(vec3 origin, vec3 dir, bool count) {
  LightRecord rec = LightRecord(vec3(0.0), LIGHT_RECORD_MISS, dir, 0.0, vec3(0.0), 0.0, vec3(0.0), 0.0);
  const ProbebakeHit hit = probebake_trace_scene(origin, dir, 0.0, 3.4e38, false);
  if (hit.triangle < 0) {
    if (count) atomicAdd(miss_count, 1u);
    rec.base = probebake_sky_radiance(dir);
    return rec;
  }
  const int tri = hit.triangle;
  const vec3 normal = probebake_hit_normal(hit);
  rec.normal = normal;
  rec.base = vec3(0.0);
  if (probebake_hit_inside(hit, normal, dir)) {
    rec.kind = LIGHT_RECORD_BACKFACE;
    if (count) atomicAdd(back_count, 1u);
    return rec;
  }
  // The front, or the back of a double-sided triangle: shaded alike with the normal facing the probe.
  rec.normal = probebake_facing_normal(normal, dir);
  if (count) atomicAdd(front_count, 1u);
  rec.kind = LIGHT_RECORD_FRONT;
  rec.position = origin + hit.t * dir;
  rec.reflect = probebake_face_material(tri).albedo * 0.318309886;
  rec.base = probebake_lighting.emissive_as_lights != 0 ? vec3(0.0) : probebake_face_material(tri).emission;
  return rec;
}

void main() {
  const uint index = probebake_flat_workgroup();
  if (index >= light_list_header.trace_count) return; // uniform per workgroup
  const uint slot = uint(light_list[push.probe_capacity + index]); // light_trace_list chose it
  const int probe = int(slot);
  const vec3 origin = probebake_probes[probe].position;
  if (gl_LocalInvocationIndex == 0) {
    hits_in_cube = 0u; hits = 0u; backface_hits = 0u;
    front_count = 0u; back_count = 0u; miss_count = 0u;
    // Streaming: a probe inside a cell that is out would only find every ray unresolved; it traces nothing
    // and keeps its records and measure.
    probe_inside_out_cell = push.null_leaf != 0u && probebake_inside_null_leaf(origin);
    unresolved_records = probe_inside_out_cell ? 1u : 0u;
  }
  barrier();
  const uint chunk = gl_WorkGroupID.z, chunks = gl_NumWorkGroups.z;
  const bool inside_out_cell = probe_inside_out_cell;
  const bool octree_probe = probebake_probes[probe].node >= 0 && !inside_out_cell;
  if (octree_probe && chunk == 0u) measure_hit_fraction(probe);
  const int rays = inside_out_cell ? 0 : probebake_lighting.rays;
  // `lanes` threads per ray: each traces the ray (the same hit), casts its share of the hit's shadow rays,
  // and the first lane sums the shares in lane order. The pass count is uniform: barriers inside.
  const uint lanes = push.trace_lanes;
  const uint lane = gl_LocalInvocationIndex % lanes, ray_in_group = gl_LocalInvocationIndex / lanes;
  const uint rays_per_group = LIGHT_WORKGROUP_SIZE / lanes, rays_per_pass = rays_per_group * chunks;
  const uint passes = (uint(rays) + rays_per_pass - 1u) / rays_per_pass;
  for (uint pass = 0u; pass < passes; ++pass) {
    const int r = int(ray_in_group + rays_per_group * (chunk + chunks * pass));
    LightRecord rec;
    vec3 emitter = vec3(0.0), punctual = vec3(0.0), tracked = vec3(0.0);
    const uint seed = probebake_record_seed(push.seed, slot, uint(r));
    probebake_ray_unresolved = false; // the hit-fraction rays above do not count
    if (r < rays) {
      rec = trace_hit(origin, probebake_ray_directions[r].xyz, lane == 0u);
      if (rec.kind == LIGHT_RECORD_FRONT) {
        emitter = probebake_emitter_irradiance_share(rec.position, rec.normal, lane, lanes);
        punctual = probebake_punctual_irradiance_share(rec.position, rec.normal, push.shadow_rays, push.tracked_light, seed,
                                                       lane, lanes, tracked);
      }
    }
    if (probebake_ray_unresolved) atomicAdd(unresolved_records, 1u);
    lane_emitter[gl_LocalInvocationIndex] = emitter;
    lane_punctual[gl_LocalInvocationIndex] = punctual;
    lane_tracked[gl_LocalInvocationIndex] = tracked;
    memoryBarrierShared();
    barrier();
    if (r < rays && lane == 0u) {
      for (uint k = 1u; k < lanes; ++k) {
        emitter += lane_emitter[gl_LocalInvocationIndex + k];
        punctual += lane_punctual[gl_LocalInvocationIndex + k];
        tracked += lane_tracked[gl_LocalInvocationIndex + k];
      }
      if (rec.kind == LIGHT_RECORD_FRONT) {
        rec.base += rec.reflect * emitter;
        light_record_set_punctual(rec, punctual); // the punctual sum (sampled past push.shadow_rays lights)
      }
      set_light_record(slot, uint(r), rec);
      if (push.tracked_light >= 0) set_tracked_punctual(slot, uint(r), tracked); // for light_relight
    }
    barrier(); // the shares are read before the next pass writes them
  }
  barrier();
  if (gl_LocalInvocationIndex != 0) return;
  // Fresh records (retraced, their punctual sums current) once every chunk is done: the last one clears the
  // flags, leaving UNRESOLVED when a chunk saw a ray cross a cell that is out (each says so before it counts
  // itself, so the last one sees it). A chunk checks the flags before it counts itself, so none can miss them.
  if (unresolved_records != 0u) atomicOr(trace_flags[slot], TRACE_FLAG_UNRESOLVED_NOW);
  const uint before = atomicAdd(trace_flags[slot], TRACE_FLAG_CHUNK_ONE);
  if (before / TRACE_FLAG_CHUNK_ONE == chunks - 1u) {
    const bool unresolved = (before & TRACE_FLAG_UNRESOLVED_NOW) != 0u;
    atomicExchange(trace_flags[slot], 0u);
    light_set_unresolved(slot, unresolved);
    if (unresolved) atomicAdd(light_counters.unresolved_probes, 1);
  }
  atomicAdd(light_counters.front_hits, int(front_count));
  atomicAdd(light_counters.backface_hits, int(back_count));
  atomicAdd(light_counters.misses, int(miss_count));
  if (chunk != 0u) return;
  if (octree_probe) {
    probebake_probes[probe].hit_fraction = float(hits_in_cube) / float(probebake_lighting.placement_rays);
    probebake_probes[probe].backface_fraction = hits > 0u ? float(backface_hits) / float(hits) : 0.0;
  }
  if (!inside_out_cell) atomicAdd(light_counters.traced_probes, 1);
}
