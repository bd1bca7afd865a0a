// Octree buffer arithmetic and the placement-lattice measure in GLSL, the twins of formats/octree.h's
// node_cube and the bake's probe tracing (placement/src/probe_tracing.cpp). The including shader declares
// VolumeInfo probebake_info, int probebake_octree[], and what bvh_trace.glsl needs plus vec4
// probebake_ray_directions[] (the lattice is ray_directions[rays, rays + placement_rays)).
#ifndef PROBEBAKE_OCTREE_GLSL
#define PROBEBAKE_OCTREE_GLSL

#include "probebake/bvh_trace.glsl"

int octree_meta_of(int node) { return node - (node - 1) % OCTREE_CLUSTER_SIZE; }
bool octree_is_node_index(int index) { return index == 0 || (index >= 1 && (index - 1) % OCTREE_CLUSTER_SIZE != 0); }
int octree_usable_elements() {
  return probebake_info.octree_elements < 1 ? 0 : 1 + ((probebake_info.octree_elements - 1) / OCTREE_CLUSTER_SIZE) * OCTREE_CLUSTER_SIZE;
}
int octree_parent_of(int node) { return node == 0 ? -1 : ~probebake_octree[octree_meta_of(node)]; }

// The root, or a node of an allocated cluster (formats: is_live_node).
bool octree_is_live_node(int node) {
  if (node == 0) return probebake_info.octree_elements > 0;
  if (node < 0 || node >= octree_usable_elements() || !octree_is_node_index(node)) return false;
  return probebake_octree[octree_meta_of(node)] < 0;
}

// The cube of octree node `node`, computed top-down exactly as formats::node_cube (precise: no FMA).
void octree_node_cube(int node, out vec3 cube_min, out float cube_size, out int cube_depth) {
  int octants[OCTREE_MAX_DEPTH];
  int depth = 0;
  while (node > 0 && depth < OCTREE_MAX_DEPTH) {
    const int meta = octree_meta_of(node);
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
  cube_depth = depth;
}

// bake::detail::Cube::exit_distance.
float octree_exit_distance(vec3 cube_min, float size, vec3 inside, vec3 dir) {
  float t = 3.4e38;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] > 0.0) t = min(t, (cube_min[a] + size - inside[a]) / dir[a]);
    else if (dir[a] < 0.0) t = min(t, (cube_min[a] - inside[a]) / dir[a]);
  }
  return max(t, 0.0);
}

// Streaming: the last measure had a lattice ray cross a cell that is out (a shader defining
// PROBEBAKE_NULL_LEAF, bvh_trace.glsl): its counts miss that cell's geometry, so it decides nothing.
bool octree_measure_unresolved = false;

// One lattice ray r (0 .. placement_rays) from `centre`: adds to the three counts, and to `unresolved` when
// it crossed a cell that is out before its hit (or anywhere, finding none).
void octree_lattice_ray(vec3 cube_min, float size, vec3 centre, int r, inout uint in_cube, inout uint hits, inout uint backface,
                        inout uint unresolved) {
  const vec3 dir = probebake_ray_directions[probebake_lighting.rays + r].xyz;
  probebake_ray_unresolved = false;
  const ProbebakeHit hit = probebake_trace_scene(centre, dir, 0.0, 3.4e38, false);
  if (probebake_ray_unresolved) unresolved += 1u;
  if (hit.triangle < 0) return;
  hits += 1u;
  if (probebake_hit_inside(hit, probebake_hit_normal(hit), dir)) backface += 1u;
  if (hit.t <= octree_exit_distance(cube_min, size, centre, dir)) in_cube += 1u;
}

// The leaf measure of a node cube, by one thread: hit fraction (hits inside the cube / lattice rays) and
// back-face fraction (back-face hits / hits), as light_trace measures it with a workgroup.
vec2 octree_measure(vec3 cube_min, float size) {
  precise const vec3 centre = cube_min + vec3(0.5 * size);
  uint in_cube = 0u, hits = 0u, backface = 0u, unresolved = 0u;
  for (int r = 0; r < probebake_lighting.placement_rays; ++r)
    octree_lattice_ray(cube_min, size, centre, r, in_cube, hits, backface, unresolved);
  octree_measure_unresolved = unresolved > 0u;
  const float f = probebake_lighting.placement_rays > 0 ? float(in_cube) / float(probebake_lighting.placement_rays) : 0.0;
  return vec2(f, hits > 0u ? float(backface) / float(hits) : 0.0);
}

#ifdef PROBEBAKE_OCTREE_GROUP_MEASURE
// The same measure by a whole workgroup (one lattice ray per invocation and step): call from uniform
// control flow; every invocation gets the result. Counts are integers, so the result equals octree_measure.
// Define PROBEBAKE_OCTREE_GROUP_MEASURE as the workgroup size (gl_WorkGroupSize is not known before the
// shader's layout declaration, which follows the includes).
shared uint octree_group_counts[4];
shared bool octree_group_inside_out_cell;

vec2 octree_measure_group(vec3 cube_min, float size) {
  if (gl_LocalInvocationIndex == 0) {
    octree_group_counts[0] = octree_group_counts[1] = octree_group_counts[2] = octree_group_counts[3] = 0u;
    // Streaming: a centre inside a cell that is out sends every lattice ray through it.
    octree_group_inside_out_cell = probebake_inside_null_leaf(cube_min + vec3(0.5 * size));
  }
  barrier();
  octree_measure_unresolved = octree_group_inside_out_cell;
  if (octree_measure_unresolved) {
    barrier(); // the flag is read before a later call writes it (uniform: every invocation returns here)
    return vec2(0.0);
  }
  precise const vec3 centre = cube_min + vec3(0.5 * size);
  uint in_cube = 0u, hits = 0u, backface = 0u, unresolved = 0u;
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.placement_rays; r += int(PROBEBAKE_OCTREE_GROUP_MEASURE))
    octree_lattice_ray(cube_min, size, centre, r, in_cube, hits, backface, unresolved);
  atomicAdd(octree_group_counts[0], in_cube);
  atomicAdd(octree_group_counts[1], hits);
  atomicAdd(octree_group_counts[2], backface);
  atomicAdd(octree_group_counts[3], unresolved);
  barrier();
  octree_measure_unresolved = octree_group_counts[3] > 0u;
  const uint rays = uint(max(probebake_lighting.placement_rays, 0));
  const vec2 m = vec2(rays > 0u ? float(octree_group_counts[0]) / float(rays) : 0.0,
                      octree_group_counts[1] > 0u ? float(octree_group_counts[2]) / float(octree_group_counts[1]) : 0.0);
  barrier(); // the counts are reused by the next call
  return m;
}
#endif

#endif // PROBEBAKE_OCTREE_GLSL
