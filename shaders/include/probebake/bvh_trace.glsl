// Ray queries against the scene's BVHs (gpu_types.h: BvhNode, TraceTriangle, DynamicObject), for devices
// without ray-tracing extensions. The GPU twin of scene::RayScene (Embree): closest hit and any hit, both
// sides of every triangle, hits with t in [t_min, t_max].
//
// Two levels (format 1.3): the static BVH, bvh_nodes[0, static nodes), then every dynamic object whose
// world box (ObjectInstance, refitted by object_refit.comp from the host's pose) the ray crosses, traced in
// object space through the object's own BVH from its bvh_root. The ray is moved into object space without
// normalising its direction, so t is the same in both spaces and one t_max serves both levels. The "top
// level" is a flat list of world boxes: a loop over tens of objects costs less than building and
// refitting a tree over them every frame.
//
// The including shader declares (std430): LightingInfo probebake_lighting (node and object counts),
// BvhNode probebake_bvh_nodes[], TraceTriangle probebake_trace_triangles[], DynamicObject
// probebake_dynamic_objects[] and ObjectInstance probebake_object_instances[] (placeholders, never read,
// when lighting.dynamic_objects is 0).
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

// Entry distance into the box [lower, upper] within [t_min, t_max], or -1 when the ray misses it.
float probebake_ray_aabb(vec3 origin, vec3 inv_dir, vec3 lower, vec3 upper, float t_min, float t_max) {
  const vec3 t0 = (lower - origin) * inv_dir;
  const vec3 t1 = (upper - origin) * inv_dir;
  const vec3 near = min(t0, t1), far = max(t0, t1);
  const float enter = max(max(near.x, near.y), max(near.z, t_min));
  const float leave = min(min(far.x, far.y), min(far.z, t_max)) * 1.0000004;
  return enter <= leave ? enter : -1.0;
}

float probebake_ray_box(vec3 origin, vec3 inv_dir, int node, float t_min, float t_max) {
  return probebake_ray_aabb(origin, inv_dir, probebake_bvh_nodes[node].lower, probebake_bvh_nodes[node].upper, t_min, t_max);
}

// Components near zero become +-1e-30 so that 1 / dir stays finite and slab tests see no 0 * inf.
vec3 probebake_safe_inverse(vec3 dir) {
  const vec3 tiny = vec3(1e-30);
  return 1.0 / mix(dir, mix(-tiny, tiny, greaterThanEqual(dir, vec3(0.0))), lessThan(abs(dir), tiny));
}

// Closest hit in the BVH rooted at `root`: the triangle index (into probebake_trace_triangles) or -1; t_max
// becomes the hit distance. any_hit: stop at the first hit found (shadow rays).
int probebake_traverse(int root, vec3 origin, vec3 dir, float t_min, inout float t_max, bool any_hit) {
  const vec3 inv_dir = probebake_safe_inverse(dir);
  int stack_node[BVH_MAX_DEPTH];
  float stack_enter[BVH_MAX_DEPTH];
  int depth = 0;
  int node = probebake_ray_box(origin, inv_dir, root, t_min, t_max) >= 0.0 ? root : -1;
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

// Nodes of the static BVH: all of them, or those before the first object's.
int probebake_static_bvh_nodes() {
  return probebake_lighting.dynamic_objects > 0 ? probebake_dynamic_objects[0].bvh_root : probebake_lighting.bvh_nodes;
}

// A hit of the scene: triangle -1 = miss; object -1 = static geometry, else the dynamic object hit.
struct ProbebakeHit {
  int triangle;
  int object;
  float t;
};

// p in the object's space (rows of object_from_world: linear part xyz, translation w).
vec3 probebake_to_object(int object, vec4 p) {
  return vec3(dot(probebake_object_instances[object].object_from_world[0], p),
              dot(probebake_object_instances[object].object_from_world[1], p),
              dot(probebake_object_instances[object].object_from_world[2], p));
}

// Closest (or, with any_hit, some) hit with t in [t_min, t_max], static geometry and every dynamic object.
ProbebakeHit probebake_trace_scene(vec3 origin, vec3 dir, float t_min, float t_max, bool any_hit) {
  ProbebakeHit hit = ProbebakeHit(-1, -1, t_max);
  float t = t_max;
  if (probebake_static_bvh_nodes() > 0) {
    hit.triangle = probebake_traverse(0, origin, dir, t_min, t, any_hit);
    if (hit.triangle >= 0 && any_hit) { hit.t = t; return hit; }
  }
  if (probebake_lighting.dynamic_objects <= 0) { hit.t = t; return hit; } // static scenes: nothing more
  const vec3 inv_dir = probebake_safe_inverse(dir);
  for (int o = 0; o < probebake_lighting.dynamic_objects; ++o) {
    if (probebake_dynamic_objects[o].bvh_node_count <= 0) continue;
    if (probebake_ray_aabb(origin, inv_dir, probebake_object_instances[o].world_lower, probebake_object_instances[o].world_upper,
                           t_min, t) < 0.0)
      continue;
    const vec3 local_origin = probebake_to_object(o, vec4(origin, 1.0));
    const vec3 local_dir = probebake_to_object(o, vec4(dir, 0.0)); // not normalised: t is the same in both spaces
    const int tri = probebake_traverse(probebake_dynamic_objects[o].bvh_root, local_origin, local_dir, t_min, t, any_hit);
    if (tri >= 0) {
      hit.triangle = tri;
      hit.object = o;
      if (any_hit) break;
    }
  }
  hit.t = t;
  return hit;
}

// The hit triangle's unit normal in world space: an object's normal through the inverse transpose of its
// linear part (the rows of object_from_world, weighted by the normal), normalised.
vec3 probebake_hit_normal(ProbebakeHit hit) {
  const vec3 n = probebake_trace_triangles[hit.triangle].normal;
  if (hit.object < 0) return n;
  const ObjectInstance inst = probebake_object_instances[hit.object];
  return normalize(n.x * inst.object_from_world[0].xyz + n.y * inst.object_from_world[1].xyz + n.z * inst.object_from_world[2].xyz);
}

// The ray arrived at the back of the triangle (the same sign in object and world space: the inverse
// transpose keeps dot(n, dir)).
bool probebake_hit_backface(ProbebakeHit hit, vec3 dir) { return dot(probebake_hit_normal(hit), dir) > 0.0; }

// The ray arrived at the back of a single-sided triangle: inside a solid (scene::RayHit::inside). The back
// of a double-sided triangle is open space like its front.
bool probebake_hit_inside(ProbebakeHit hit, vec3 dir) {
  return probebake_hit_backface(hit, dir) && (probebake_trace_triangles[hit.triangle].flags & TRIANGLE_DOUBLE_SIDED) == 0u;
}

// The unit world-space normal of the side the ray arrived at (scene::RayHit::facing_normal).
vec3 probebake_hit_facing_normal(ProbebakeHit hit, vec3 dir) {
  const vec3 n = probebake_hit_normal(hit);
  return dot(n, dir) > 0.0 ? -n : n;
}

bool probebake_occluded(vec3 origin, vec3 dir, float t_min, float t_max) {
  return probebake_trace_scene(origin, dir, t_min, t_max, true).triangle >= 0;
}

#endif // PROBEBAKE_BVH_TRACE_GLSL
