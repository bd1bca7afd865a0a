// One SVO leaf's stencil in GLSL: the walk down the probe index, steps 1-2 of the lookup (lookup.h), and
// E_leaf. Included by probebake/sample_irradiance.glsl once the volume's buffers are declared; the light
// update's bounce uses the one-leaf lookup (probebake_svo_stencil) on its own.
#ifndef PROBEBAKE_SVO_STENCIL_GLSL
#define PROBEBAKE_SVO_STENCIL_GLSL

// Up to four probes with final, normalised weights; probes.x < 0 means a miss.
struct ProbebakeStencil {
  ivec4 probes;
  vec4 weights;
};

// Half an SVO voxel (step 1).
float probebake_normal_bias() {
  return 0.5 * probebake_info.root_size / float(1 << clamp(probebake_info.svo_depth, 0, 30));
}

// A walk down the SVO towards finest voxel `c` (in range): `node`'s children split on bit `level` of the
// coordinates (the root's on bit svo_depth - 1; a node at level -1 must be a leaf). `ended`: at a leaf
// (leaf >= 0) or at an empty node or a bad index (leaf -1).
struct ProbebakeWalk {
  int node;
  int level;
  bool ended;
  int leaf;
};

// Walks the levels from w.level down to `last` (inclusive), or until the walk ends.
ProbebakeWalk probebake_walk(ProbebakeWalk w, ivec3 c, int last) {
  for (; w.level >= last; --w.level) {
    const int v = probebake_svo_nodes[w.node];
    w.ended = v <= 0 || w.level < 0;
    if (w.ended) {
      w.leaf = v < 0 && ~v < probebake_info.svo_leaves ? ~v : -1;
      return w;
    }
    const int octant = ((c.x >> w.level) & 1) | (((c.y >> w.level) & 1) << 1) | (((c.z >> w.level) & 1) << 2);
    if (v > probebake_info.svo_nodes - 1 - octant) { // v + octant >= svo_nodes, without overflow
      w.ended = true;
      w.leaf = -1;
      return w;
    }
    w.node = v + octant;
  }
  return w;
}

// Descent to the leaf holding finest voxel `c` (in range): index into probebake_svo_leaves or -1.
int probebake_leaf_of_voxel(ivec3 c) {
  return probebake_walk(ProbebakeWalk(0, probebake_info.svo_depth - 1, false, -1), c, -1).leaf;
}

bool probebake_has_svo() {
  return probebake_info.svo_nodes > 0 && probebake_info.svo_depth >= 0 && probebake_info.svo_depth <= 30;
}

// p relative to the root cube: true when inside it (max faces included), false outside or not finite.
bool probebake_root_relative(vec3 p, out vec3 t) {
  t = (p - probebake_info.root_min) / probebake_info.root_size;
  return t.x >= 0.0 && t.y >= 0.0 && t.z >= 0.0 && t.x <= 1.0 && t.y <= 1.0 && t.z <= 1.0;
}

// The finest voxel holding root-relative point t.
ivec3 probebake_voxel_of(vec3 t) {
  const int n = 1 << probebake_info.svo_depth;
  return clamp(ivec3(floor(t * float(n))), ivec3(0), ivec3(n - 1));
}

// Index into probebake_svo_leaves of the leaf containing p, or -1.
int probebake_find_svo_leaf(vec3 p) {
  vec3 t;
  if (!probebake_has_svo() || !probebake_root_relative(p, t)) return -1;
  return probebake_leaf_of_voxel(probebake_voxel_of(t));
}

// ((dot(n, dir) + 1) / 2)^2 + 0.05, dir towards the probe from the shaded point (zero on the probe).
float probebake_backface_weight(vec3 normal, vec3 to_probe) {
  const vec3 dir = to_probe * (1.0 / sqrt(max(dot(to_probe, to_probe), 1e-30)));
  const float c = 0.5 * (dot(normal, dir) + 1.0);
  return c * c + 0.05;
}

// Step 2 for leaf `leaf` (a miss for -1).
ProbebakeStencil probebake_leaf_stencil(int leaf, vec3 position, vec3 normal) {
  ProbebakeStencil s = ProbebakeStencil(ivec4(-1), vec4(0.0));
  if (leaf < 0) return s;
  const SvoLeaf l = probebake_svo_leaves[leaf];
  vec4 w = vec4(0.0);
  float sum = 0.0;
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
    const int probe = l.probes[k];
    if (probe < 0 || probe >= probebake_info.probe_capacity) continue;
    w[k] = l.weights[k] * probebake_backface_weight(normal, probebake_probe_position(probe) - position);
    sum += w[k];
  }
  if (!(sum > 0.0)) return s;
  int used = 0;
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
    if (w[k] <= 0.0) continue;
    s.probes[used] = l.probes[k];
    s.weights[used] = w[k] / sum;
    ++used;
  }
  return s;
}

// The stencil of p''s own leaf: the lookup of the light update's bounce (probe_index::svo_stencil).
ProbebakeStencil probebake_svo_stencil(vec3 position, vec3 normal) {
  return probebake_leaf_stencil(probebake_find_svo_leaf(position + normal * probebake_normal_bias()), position,
                                normal);
}

// E_leaf of one leaf's stencil (step 2): the light update's bounce lookup.
vec3 probebake_apply_stencil(ProbebakeStencil s, vec3 normal) {
  vec3 e = vec3(0.0);
  if (s.probes.x < 0) return e;
  float y[9];
  probebake_sh_basis(normal, y);
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
    if (s.probes[k] < 0) continue;
    e += s.weights[k] * max(probebake_evaluate_probe_sh(s.probes[k], y), vec3(0.0));
  }
  return e;
}

#endif // PROBEBAKE_SVO_STENCIL_GLSL
