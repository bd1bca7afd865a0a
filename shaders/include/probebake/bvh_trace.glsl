// Ray queries against the static scene's BVH (gpu_types.h: BvhNode, TraceTriangle), for devices without
// ray-tracing extensions. The GPU twin of scene::RayScene (Embree): closest hit and any hit, both sides of
// every triangle, hits with t in [t_min, t_max].
//
// The including shader declares (std430): LightingInfo probebake_lighting (for the node count),
// BvhNode probebake_bvh_nodes[], TraceTriangle probebake_trace_triangles[].
//
// Traversal: a stack of BVH_MAX_DEPTH nodes, nearer child first, far children skipped once the closest hit
// is nearer than their entry distance. Box exits are widened by a few ulps so that rounding never culls a
// triangle lying in a box face (axis-aligned walls make flat boxes).
#ifndef PROBEBAKE_BVH_TRACE_GLSL
#define PROBEBAKE_BVH_TRACE_GLSL

// Moller-Trumbore; t of the hit or -1. Both faces count (Embree's default).
float probebake_ray_triangle(vec3 origin, vec3 dir, int index) {
  const vec3 v0 = probebake_trace_triangles[index].v0;
  const vec3 e1 = probebake_trace_triangles[index].edge1;
  const vec3 e2 = probebake_trace_triangles[index].edge2;
  const vec3 p = cross(dir, e2);
  const float det = dot(e1, p);
  if (det == 0.0) return -1.0;
  const float inv = 1.0 / det;
  const vec3 s = origin - v0;
  const float u = dot(s, p) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const vec3 q = cross(s, e1);
  const float v = dot(dir, q) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return dot(e2, q) * inv;
}

// Entry distance into node's box within [t_min, t_max], or -1 when the ray misses it.
float probebake_ray_box(vec3 origin, vec3 inv_dir, int node, float t_min, float t_max) {
  const vec3 t0 = (probebake_bvh_nodes[node].lower - origin) * inv_dir;
  const vec3 t1 = (probebake_bvh_nodes[node].upper - origin) * inv_dir;
  const vec3 near = min(t0, t1), far = max(t0, t1);
  const float enter = max(max(near.x, near.y), max(near.z, t_min));
  const float leave = min(min(far.x, far.y), min(far.z, t_max)) * 1.0000004;
  return enter <= leave ? enter : -1.0;
}

// Components near zero become +-1e-30 so that 1 / dir stays finite and slab tests see no 0 * inf.
vec3 probebake_safe_inverse(vec3 dir) {
  const vec3 tiny = vec3(1e-30);
  return 1.0 / mix(dir, mix(-tiny, tiny, greaterThanEqual(dir, vec3(0.0))), lessThan(abs(dir), tiny));
}

// Closest hit: the triangle index (into probebake_trace_triangles) or -1; t_max becomes the hit distance.
// any_hit: stop at the first hit found (shadow rays).
int probebake_trace(vec3 origin, vec3 dir, float t_min, inout float t_max, bool any_hit) {
  if (probebake_lighting.bvh_nodes <= 0) return -1;
  const vec3 inv_dir = probebake_safe_inverse(dir);
  int stack_node[BVH_MAX_DEPTH];
  float stack_enter[BVH_MAX_DEPTH];
  int depth = 0;
  int node = probebake_ray_box(origin, inv_dir, 0, t_min, t_max) >= 0.0 ? 0 : -1;
  int hit = -1;
  while (true) {
    if (node < 0) {
      // Pop the nearest pending far child that can still hold a closer hit.
      while (depth > 0 && node < 0) {
        --depth;
        if (stack_enter[depth] <= t_max) node = stack_node[depth];
      }
      if (node < 0) break;
    }
    const int count = probebake_bvh_nodes[node].count;
    const int first = probebake_bvh_nodes[node].first;
    if (count > 0) {
      for (int i = first; i < first + count; ++i) {
        const float t = probebake_ray_triangle(origin, dir, i);
        if (t >= t_min && t <= t_max && (hit < 0 || t < t_max)) {
          t_max = t;
          hit = i;
          if (any_hit) return hit;
        }
      }
      node = -1;
      continue;
    }
    const float a = probebake_ray_box(origin, inv_dir, first, t_min, t_max);
    const float b = probebake_ray_box(origin, inv_dir, first + 1, t_min, t_max);
    if (a >= 0.0 && b >= 0.0) {
      const bool a_first = a <= b;
      if (depth < BVH_MAX_DEPTH) { // the bake keeps the tree shallower than the stack (validate: bvh_tree)
        stack_node[depth] = a_first ? first + 1 : first;
        stack_enter[depth] = a_first ? b : a;
        ++depth;
      }
      node = a_first ? first : first + 1;
    } else {
      node = a >= 0.0 ? first : (b >= 0.0 ? first + 1 : -1);
    }
  }
  return hit;
}

// The ray arrived at the back of a single-sided triangle: inside a solid (scene::RayHit::inside). The back
// of a double-sided triangle is open space like its front.
bool probebake_backface(int index, vec3 dir) { return dot(probebake_trace_triangles[index].normal, dir) > 0.0; }

bool probebake_inside(int index, vec3 dir) {
  return probebake_backface(index, dir) && (probebake_trace_triangles[index].flags & TRIANGLE_DOUBLE_SIDED) == 0u;
}

// The unit normal of the side the ray arrived at (scene::RayHit::facing_normal).
vec3 probebake_facing_normal(int index, vec3 dir) {
  const vec3 n = probebake_trace_triangles[index].normal;
  return probebake_backface(index, dir) ? -n : n;
}

bool probebake_occluded(vec3 origin, vec3 dir, float t_min, float t_max) {
  return probebake_trace(origin, dir, t_min, t_max, true) >= 0;
}

#endif // PROBEBAKE_BVH_TRACE_GLSL
