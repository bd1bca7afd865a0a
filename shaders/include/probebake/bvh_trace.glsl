// Ray queries against the scene's BVHs (gpu_types.h "Compact tracing": TraceTree, TraceNode, TraceFace,
// TraceVertex, TraceMaterial; DynamicObject), for devices without ray-tracing extensions. The GPU twin of
// scene::RayScene (Embree): closest hit and any hit, both sides of every triangle, hits with t in
// [t_min, t_max].
//
// Two levels (format 1.3): the static tree (trace_trees[0]), then every dynamic object whose world box
// (ObjectInstance, refitted by object_refit.comp from the host's pose) the ray crosses, traced in object
// space through its own tree (trace_trees[1 + o]). The ray is moved into object space without normalising
// its direction, so t is the same in both spaces and one t_max serves both levels. The "top level" is a
// flat list of world boxes: a loop over tens of objects costs less than building and refitting a tree
// over them every frame.
//
// The including shader declares (std430): LightingInfo probebake_lighting (counts), TraceTree
// probebake_trace_trees[], TraceNode probebake_trace_nodes[], TraceFace probebake_trace_faces[], TraceVertex
// probebake_trace_vertices[], TraceMaterial probebake_trace_materials[], DynamicObject
// probebake_dynamic_objects[] and ObjectInstance probebake_object_instances[] (placeholders, never read,
// when lighting.dynamic_objects is 0).
//
// Traversal: a stack of BVH_MAX_DEPTH child words, nearer child first, far children skipped once the
// closest hit is nearer than their entry distance. A node holds both children's boxes, 16-bit in the tree's
// frame and rounded outwards by the bake (formats/trace_mesh.h), so one node read decides both. Box exits
// are widened by a few ulps so that rounding never culls a triangle lying in a box face (axis-aligned walls
// make flat boxes).
//
// Streaming (docs/RUNTIME.md "Streaming cells"): a cell that is out is reached through a leaf of the null
// face, which no ray hits. A shader that defines PROBEBAKE_NULL_LEAF (that word) learns whether a ray could
// have hit something there: probebake_trace_scene sets probebake_ray_unresolved when the ray entered such
// a leaf's box before its hit (or, finding none, anywhere), and never clears it.
#ifndef PROBEBAKE_BVH_TRACE_GLSL
#define PROBEBAKE_BVH_TRACE_GLSL

// Nearest entry into a null leaf's box of the current static traversal, when one was entered (a flag, not a
// large sentinel: a miss's t is t_max, which may be as large as any sentinel).
bool probebake_null_entered = false;
float probebake_null_enter = 0.0;
bool probebake_ray_unresolved = false;

vec3 probebake_trace_vertex(uint i) {
  return vec3(probebake_trace_vertices[i].x, probebake_trace_vertices[i].y, probebake_trace_vertices[i].z);
}

// Moller-Trumbore on v0 and the edges to v1 and v2 (the same float subtractions as the CPU's
// formats::face_geometry); t of the hit or -1. Both faces count (Embree's default).
float probebake_ray_triangle(vec3 origin, vec3 dir, int face) {
  const TraceFace f = probebake_trace_faces[face]; // one 16-byte read
  const vec3 v0 = probebake_trace_vertex(f.vertex[0]);
  const vec3 e1 = probebake_trace_vertex(f.vertex[1]) - v0;
  const vec3 e2 = probebake_trace_vertex(f.vertex[2]) - v0;
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

TraceMaterial probebake_face_material(int face) {
  return probebake_trace_materials[probebake_trace_faces[face].material & TRACE_MATERIAL_MASK];
}

// Unit normal of the counter-clockwise front face in the face's own space; (0, 0, 1) for a face without
// area, which the bake leaves out and the validator refuses, so that no NaN can come of a hostile file.
vec3 probebake_face_normal(int face) {
  const vec3 v0 = probebake_trace_vertex(probebake_trace_faces[face].vertex[0]);
  const vec3 n = cross(probebake_trace_vertex(probebake_trace_faces[face].vertex[1]) - v0,
                       probebake_trace_vertex(probebake_trace_faces[face].vertex[2]) - v0);
  const float length_squared = dot(n, n);
  return length_squared > 0.0 && length_squared < 3.4e38 ? n * inversesqrt(length_squared) : vec3(0.0, 0.0, 1.0);
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

// Component `shift` (0: child 0, 16: child 1) of a packed coordinate, decoded in the tree's frame.
vec3 probebake_decode(uint x, uint y, uint z, uint shift, vec3 frame_lower, vec3 frame_scale) {
  return frame_lower + vec3(uvec3(x, y, z) >> shift & 0xFFFFu) * frame_scale;
}

// Entry distances into the two children's boxes of node `n` (-1: missed).
vec2 probebake_child_entries(TraceNode n, vec3 origin, vec3 inv_dir, vec3 frame_lower, vec3 frame_scale, float t_min, float t_max) {
  const uint lx = n.lower[0], ly = n.lower[1], lz = n.lower[2];
  const uint ux = n.upper[0], uy = n.upper[1], uz = n.upper[2];
  return vec2(probebake_ray_aabb(origin, inv_dir, probebake_decode(lx, ly, lz, 0u, frame_lower, frame_scale),
                                 probebake_decode(ux, uy, uz, 0u, frame_lower, frame_scale), t_min, t_max),
              probebake_ray_aabb(origin, inv_dir, probebake_decode(lx, ly, lz, 16u, frame_lower, frame_scale),
                                 probebake_decode(ux, uy, uz, 16u, frame_lower, frame_scale), t_min, t_max));
}

// Components near zero become +-1e-30 so that 1 / dir stays finite and slab tests see no 0 * inf.
vec3 probebake_safe_inverse(vec3 dir) {
  const vec3 tiny = vec3(1e-30);
  return 1.0 / mix(dir, mix(-tiny, tiny, greaterThanEqual(dir, vec3(0.0))), lessThan(abs(dir), tiny));
}

// Closest hit in tree `tree` (0 static, 1 + o object o): the face index or -1; t_max becomes the hit
// distance. any_hit: stop at the first hit found (shadow rays).
int probebake_traverse(int tree, vec3 origin, vec3 dir, float t_min, inout float t_max, bool any_hit) {
  const uint root = probebake_trace_trees[tree].root;
  if (root == TRACE_NO_ROOT) return -1;
  const vec3 frame_lower = probebake_trace_trees[tree].lower, frame_scale = probebake_trace_trees[tree].scale;
  const vec3 inv_dir = probebake_safe_inverse(dir);
  const float root_enter = probebake_ray_aabb(origin, inv_dir, frame_lower, frame_lower + float(TRACE_BOX_STEPS) * frame_scale, t_min, t_max);
  if (root_enter < 0.0) return -1;
  uint stack_child[BVH_MAX_DEPTH];
  float stack_enter[BVH_MAX_DEPTH];
  int depth = 0;
  uint child = root;
  float child_enter = root_enter; // where the ray enters `child`'s box
  bool pending = true;
  int hit = -1;
  while (true) {
    if (!pending) {
      // Pop the nearest pending far child that can still hold a closer hit.
      while (depth > 0 && !pending) {
        --depth;
        if (stack_enter[depth] <= t_max) child = stack_child[depth], child_enter = stack_enter[depth], pending = true;
      }
      if (!pending) break;
    }
    if ((child & TRACE_CHILD_LEAF) != 0u) {
#ifdef PROBEBAKE_NULL_LEAF
      if (child == PROBEBAKE_NULL_LEAF) {
        probebake_null_enter = probebake_null_entered ? min(probebake_null_enter, child_enter) : child_enter;
        probebake_null_entered = true;
      }
#endif
      const int first = int(child & TRACE_LEAF_FIRST_MASK);
      const int count = int(child >> TRACE_LEAF_COUNT_SHIFT & 15u) + 1;
      for (int i = first; i < first + count; ++i) {
        const float t = probebake_ray_triangle(origin, dir, i);
        if (t >= t_min && t <= t_max && (hit < 0 || t < t_max)) {
          t_max = t;
          hit = i;
          if (any_hit) return hit;
        }
      }
      pending = false;
      continue;
    }
    const TraceNode node = probebake_trace_nodes[child]; // one 32-byte read decides both children
    const vec2 enter = probebake_child_entries(node, origin, inv_dir, frame_lower, frame_scale, t_min, t_max);
    const uint child0 = node.child[0], child1 = node.child[1];
    if (enter.x >= 0.0 && enter.y >= 0.0) {
      const bool first_nearer = enter.x <= enter.y;
      if (depth < BVH_MAX_DEPTH) { // the bake keeps the tree shallower than the stack (validate: trace_tree)
        stack_child[depth] = first_nearer ? child1 : child0;
        stack_enter[depth] = first_nearer ? enter.y : enter.x;
        ++depth;
      }
      child = first_nearer ? child0 : child1;
      child_enter = first_nearer ? enter.x : enter.y;
    } else {
      pending = enter.x >= 0.0 || enter.y >= 0.0;
      child = enter.x >= 0.0 ? child0 : child1;
      child_enter = enter.x >= 0.0 ? enter.x : enter.y;
    }
  }
  return hit;
}

// A hit of the scene: triangle (a face index) -1 = miss; object -1 = static geometry, else the dynamic object hit.
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
// The static tree's null leaves entered before `t` (the hit, or t_max for none): the ray is unresolved.
void probebake_note_unresolved(float t) {
#ifdef PROBEBAKE_NULL_LEAF
  if (probebake_null_entered && probebake_null_enter <= t) probebake_ray_unresolved = true;
#endif
}

// Streaming: whether `p` lies inside the box of a null leaf (a cell that is out): every ray from it enters
// that leaf at t = 0, before any hit, so it is unresolved whatever it would hit. A traversal that reaches
// only the boxes holding `p` (t_max = 0).
bool probebake_inside_null_leaf(vec3 p) {
#ifdef PROBEBAKE_NULL_LEAF
  float t = 0.0;
  probebake_null_entered = false;
  probebake_traverse(0, p, vec3(0.0, 1.0, 0.0), 0.0, t, false);
  return probebake_null_entered;
#else
  return false;
#endif
}

ProbebakeHit probebake_trace_scene(vec3 origin, vec3 dir, float t_min, float t_max, bool any_hit) {
  ProbebakeHit hit = ProbebakeHit(-1, -1, t_max);
  float t = t_max;
  probebake_null_entered = false;
  hit.triangle = probebake_traverse(0, origin, dir, t_min, t, any_hit);
  if (hit.triangle >= 0 && any_hit) { hit.t = t; return hit; } // occluded, whatever is out
  if (probebake_lighting.dynamic_objects <= 0) { hit.t = t; probebake_note_unresolved(t); return hit; } // static scenes: nothing more
  const vec3 inv_dir = probebake_safe_inverse(dir);
  for (int o = 0; o < probebake_lighting.dynamic_objects; ++o) {
    if (probebake_ray_aabb(origin, inv_dir, probebake_object_instances[o].world_lower, probebake_object_instances[o].world_upper,
                           t_min, t) < 0.0)
      continue;
    const vec3 local_origin = probebake_to_object(o, vec4(origin, 1.0));
    const vec3 local_dir = probebake_to_object(o, vec4(dir, 0.0)); // not normalised: t is the same in both spaces
    const int tri = probebake_traverse(1 + o, local_origin, local_dir, t_min, t, any_hit);
    if (tri >= 0) {
      hit.triangle = tri;
      hit.object = o;
      if (any_hit) { hit.t = t; return hit; } // occluded, whatever is out
    }
  }
  hit.t = t;
  probebake_note_unresolved(t);
  return hit;
}

// The hit triangle's unit normal in world space: an object's normal through the inverse transpose of its
// linear part (the rows of object_from_world, weighted by the normal), normalised.
vec3 probebake_hit_normal(ProbebakeHit hit) {
  const vec3 n = probebake_face_normal(hit.triangle);
  if (hit.object < 0) return n;
  const ObjectInstance inst = probebake_object_instances[hit.object];
  return normalize(n.x * inst.object_from_world[0].xyz + n.y * inst.object_from_world[1].xyz + n.z * inst.object_from_world[2].xyz);
}

// The ray arrived at the back of a single-sided triangle: inside a solid (scene::RayHit::inside). The back
// of a double-sided triangle is open space like its front. `normal` is probebake_hit_normal(hit), computed
// once per hit by the caller (three vertex reads and a normalisation); the inverse transpose keeps the sign
// of dot(n, dir), so object hits are decided alike in both spaces.
bool probebake_hit_inside(ProbebakeHit hit, vec3 normal, vec3 dir) {
  return dot(normal, dir) > 0.0 && (probebake_trace_faces[hit.triangle].material & TRACE_FACE_DOUBLE_SIDED) == 0u;
}

// The unit world-space normal of the side the ray arrived at (scene::RayHit::facing_normal), from the hit's
// normal.
vec3 probebake_facing_normal(vec3 normal, vec3 dir) { return dot(normal, dir) > 0.0 ? -normal : normal; }

bool probebake_occluded(vec3 origin, vec3 dir, float t_min, float t_max) {
  return probebake_trace_scene(origin, dir, t_min, t_max, true).triangle >= 0;
}

#endif // PROBEBAKE_BVH_TRACE_GLSL
