// Light update L1 (octree thesis §3.2.2, "place surfels"): one workgroup per probe slot.
//  - Hit fraction: the placement lattice (ray_directions[rays, rays + placement_rays)) traced from the
//    centre of the probe's octree node, hits counted inside the node cube (bake/src/probe_tracing.cpp);
//    octree probes only (grid probes keep the bake's value).
//  - Lighting rays: ray_directions[0, rays) from the probe to the nearest hit at any distance, each kept as
//    a LightRecord with what does not change from frame to frame (bake/src/lighting/hit_cache.cpp).
//  Both use the bake's sides rule (glTF doubleSided): only the back of a single-sided triangle is inside
//  geometry (a back-face hit and record); the back of a double-sided one is shaded with the facing normal.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_PROBES_WRITABLE
#include "probebake/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/direct_light.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

shared uint hits_in_cube, hits, backface_hits;
shared uint front_count, back_count, miss_count;

// The cube of octree node `node`, computed top-down exactly as formats::node_cube (precise: no FMA).
void node_cube(int node, out vec3 cube_min, out float cube_size) {
  int octants[OCTREE_MAX_DEPTH];
  int depth = 0;
  while (node > 0 && depth < OCTREE_MAX_DEPTH) {
    const int meta = node - (node - 1) % OCTREE_CLUSTER_SIZE;
    octants[depth++] = node - meta - 1;
    node = ~probebake_octree[meta];
  }
  precise vec3 m = probebake_info.root_min;
  precise float size = probebake_info.root_size;
  for (int level = depth - 1; level >= 0; --level) {
    const int o = octants[level];
    const float half_size = 0.5 * size;
    m = m + vec3(float(o & 1), float((o >> 1) & 1), float((o >> 2) & 1)) * half_size;
    size = half_size;
  }
  cube_min = m;
  cube_size = size;
}

// bake::detail::Cube::exit_distance.
float exit_distance(vec3 cube_min, float size, vec3 inside, vec3 dir) {
  float t = 3.4e38;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] > 0.0) t = min(t, (cube_min[a] + size - inside[a]) / dir[a]);
    else if (dir[a] < 0.0) t = min(t, (cube_min[a] - inside[a]) / dir[a]);
  }
  return max(t, 0.0);
}

void measure_hit_fraction(int probe) {
  vec3 cube_min;
  float size;
  node_cube(probebake_probes[probe].node, cube_min, size);
  precise const vec3 centre = cube_min + vec3(0.5 * size);
  const int first = probebake_lighting.rays;
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.placement_rays; r += int(LIGHT_WORKGROUP_SIZE)) {
    const vec3 dir = probebake_ray_directions[first + r].xyz;
    float t = 3.4e38;
    const int tri = probebake_trace(centre, dir, 0.0, t, false);
    if (tri < 0) continue;
    atomicAdd(hits, 1u);
    if (probebake_inside(tri, dir)) atomicAdd(backface_hits, 1u);
    if (t <= exit_distance(cube_min, size, centre, dir)) atomicAdd(hits_in_cube, 1u);
  }
}

LightRecord trace_record(vec3 origin, vec3 dir) {
  LightRecord rec = LightRecord(vec3(0.0), LIGHT_RECORD_MISS, vec3(0.0), 0.0, probebake_lighting.sky_radiance, 0.0,
                                vec3(0.0), 0.0);
  float t = 3.4e38;
  const int tri = probebake_trace(origin, dir, 0.0, t, false);
  if (tri < 0) {
    atomicAdd(miss_count, 1u);
    return rec;
  }
  rec.normal = probebake_trace_triangles[tri].normal;
  rec.base = vec3(0.0);
  if (probebake_inside(tri, dir)) {
    rec.kind = LIGHT_RECORD_BACKFACE;
    atomicAdd(back_count, 1u);
    return rec;
  }
  // The front, or the back of a double-sided triangle: shaded alike with the normal facing the probe.
  rec.normal = probebake_facing_normal(tri, dir);
  atomicAdd(front_count, 1u);
  rec.kind = LIGHT_RECORD_FRONT;
  rec.position = origin + t * dir;
  rec.reflect = probebake_trace_triangles[tri].albedo * 0.318309886;
  const vec3 emitted = probebake_lighting.emissive_as_lights != 0 ? vec3(0.0) : probebake_trace_triangles[tri].emission;
  rec.base = emitted + rec.reflect * probebake_emitter_irradiance(rec.position, rec.normal);
  return rec;
}

void main() {
  const uint slot = probebake_flat_workgroup();
  if (slot >= push.probe_capacity || probebake_probes[slot].link == 0) return; // uniform per workgroup
  const int probe = int(slot);
  if (gl_LocalInvocationIndex == 0) {
    hits_in_cube = 0u; hits = 0u; backface_hits = 0u;
    front_count = 0u; back_count = 0u; miss_count = 0u;
  }
  barrier();
  const bool octree_probe = probebake_probes[probe].node >= 0;
  if (octree_probe) measure_hit_fraction(probe);
  const vec3 origin = probebake_probes[probe].position;
  const int rays = probebake_lighting.rays;
  for (int r = int(gl_LocalInvocationIndex); r < rays; r += int(LIGHT_WORKGROUP_SIZE))
    light_records[slot * uint(rays) + uint(r)] = trace_record(origin, probebake_ray_directions[r].xyz);
  barrier();
  if (gl_LocalInvocationIndex != 0) return;
  if (octree_probe) {
    probebake_probes[probe].hit_fraction = float(hits_in_cube) / float(probebake_lighting.placement_rays);
    probebake_probes[probe].backface_fraction = hits > 0u ? float(backface_hits) / float(hits) : 0.0;
  }
  atomicAdd(light_counters.traced_probes, 1);
  atomicAdd(light_counters.front_hits, int(front_count));
  atomicAdd(light_counters.backface_hits, int(back_count));
  atomicAdd(light_counters.misses, int(miss_count));
}
