// Irradiance lookup from a probebake volume in GLSL: include this in your own shader to sample the same
// storage buffers the runtime uploads (Volume::buffers() in runtime/include/probebake/runtime/runtime.h).
// It is the GPU twin of bake::sample_irradiance (bake/lighting/include/probebake/bake/sampler.h), step for step:
//   1. p' = position + normal * (half an SVO voxel); outside the root cube: a miss;
//   2. a leaf's stencil: up to four probes, stored weight * DDGI's smooth back-face weight, normalised;
//   3. the blend: the eight finest-voxel centres around p' look up their leaves (SVO descent), weighted
//      trilinearly and by the side of the surface's plane they lie on; only leaves joined to p''s own by
//      leaves sharing a probe stay; the result is continuous across leaf borders; one descent when all
//      eight lie in p''s own leaf;
//   4. sum over the blend's leaves of weight * sum of stencil weight * max(0, probe SH irradiance).
//
// Requires: #version 450 or later, GL_GOOGLE_include_directive, include path shaders/include.
// Buffers (std430, read-only), declared here unless PROBEBAKE_DECLARE_BUFFERS is defined to 0, in which case
// the including shader declares the four names below itself (e.g. through buffer references):
//   PROBEBAKE_BINDING_VOLUME_INFO (default 0): VolumeInfo probebake_info        <- Volume::buffers().volume_info
//   PROBEBAKE_BINDING_PROBES      (default 1): Probe probebake_probes[]         <- .probes
//   PROBEBAKE_BINDING_SVO_NODES   (default 2): int probebake_svo_nodes[]        <- .svo_nodes
//   PROBEBAKE_BINDING_SVO_LEAVES  (default 3): SvoLeaf probebake_svo_leaves[]   <- .svo_leaves
// all in descriptor set PROBEBAKE_SET (default 0). Define the macros before the #include to move them (an
// integer literal or any GLSL constant expression); the defaults are SAMPLE_BINDING_* of probebake/bindings.h.
// An empty SVO section has no buffer: bind any buffer of at least 4 bytes there (info.svo_nodes == 0 makes
// every lookup a miss without reading it).
//
// Entry point: vec3 probebake_sample_irradiance(vec3 position, vec3 normal), world space metres, unit
// normal; returns W/m^2 (0 on a miss). Punctual lights are not in the probes (docs/LIGHTING.md).
//
// Streaming (docs/RUNTIME.md "Streaming cells"): define PROBEBAKE_BINDING_RECORD_SLOTS to also get
// int probebake_record_slots[] (<- Volume::buffers().record_slots, same set) and
// bool probebake_sample_irradiance_not_lit(vec3 position, vec3 normal, out vec3 irradiance): true when a
// probe of the lookup has no light records (its cell is out of range, or past UploadOptions::streaming's
// max_lit_probes) or is unresolved (its rays crossed a cell that is out: RECORD_SLOT_UNRESOLVED), so that
// its irradiance is the file's or the last lit value, not relit this frame.
#ifndef PROBEBAKE_SAMPLE_IRRADIANCE_GLSL
#define PROBEBAKE_SAMPLE_IRRADIANCE_GLSL

#include "probebake/bindings.h"
#include "probebake/gpu_types.h"
#include "probebake/sh.glsl"

#ifndef PROBEBAKE_SET
#define PROBEBAKE_SET 0
#endif
// Defaults: the runtime's own sampling pass layout (SAMPLE_BINDING_* in bindings.h, 0-3).
#ifndef PROBEBAKE_BINDING_VOLUME_INFO
#define PROBEBAKE_BINDING_VOLUME_INFO SAMPLE_BINDING_VOLUME_INFO
#endif
#ifndef PROBEBAKE_BINDING_PROBES
#define PROBEBAKE_BINDING_PROBES SAMPLE_BINDING_PROBES
#endif
#ifndef PROBEBAKE_BINDING_SVO_NODES
#define PROBEBAKE_BINDING_SVO_NODES SAMPLE_BINDING_SVO_NODES
#endif
#ifndef PROBEBAKE_BINDING_SVO_LEAVES
#define PROBEBAKE_BINDING_SVO_LEAVES SAMPLE_BINDING_SVO_LEAVES
#endif
#ifndef PROBEBAKE_DECLARE_BUFFERS
#define PROBEBAKE_DECLARE_BUFFERS 1
#endif

#if PROBEBAKE_DECLARE_BUFFERS
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_VOLUME_INFO) readonly buffer ProbebakeVolumeInfo {
  VolumeInfo probebake_info;
};
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_PROBES) readonly buffer ProbebakeProbes {
  Probe probebake_probes[];
};
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_SVO_NODES) readonly buffer ProbebakeSvoNodes {
  int probebake_svo_nodes[];
};
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_SVO_LEAVES) readonly buffer ProbebakeSvoLeaves {
  SvoLeaf probebake_svo_leaves[];
};
#endif

// Up to four probes with final, normalised weights; probes.x < 0 means a miss.
struct ProbebakeStencil {
  ivec4 probes;
  vec4 weights;
};

// Half an SVO voxel (step 1).
float probebake_normal_bias() {
  return 0.5 * probebake_info.root_size / float(1 << clamp(probebake_info.svo_depth, 0, 30));
}

// Descent to the leaf holding finest voxel `c` (in range): index into probebake_svo_leaves or -1;
// `leaf_depth` receives the leaf node's depth (root 0).
int probebake_leaf_of_voxel(ivec3 c, out int leaf_depth) {
  const int depth = probebake_info.svo_depth;
  leaf_depth = 0;
  int node = 0;
  for (int level = depth - 1; level >= -1; --level) {
    const int v = probebake_svo_nodes[node];
    if (v < 0) {
      leaf_depth = depth - 1 - level;
      return ~v < probebake_info.svo_leaves ? ~v : -1;
    }
    if (v == 0 || level < 0) return -1;
    const int octant = ((c.x >> level) & 1) | (((c.y >> level) & 1) << 1) | (((c.z >> level) & 1) << 2);
    if (v > probebake_info.svo_nodes - 1 - octant) return -1; // v + octant >= svo_nodes, without overflow
    node = v + octant;
  }
  return -1;
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

// Index into probebake_svo_leaves of the leaf containing p, or -1; `leaf_depth` as above.
int probebake_find_svo_leaf(vec3 p, out int leaf_depth) {
  leaf_depth = 0;
  vec3 t;
  if (!probebake_has_svo() || !probebake_root_relative(p, t)) return -1;
  return probebake_leaf_of_voxel(probebake_voxel_of(t), leaf_depth);
}

int probebake_find_svo_leaf(vec3 p) {
  int leaf_depth;
  return probebake_find_svo_leaf(p, leaf_depth);
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
    w[k] = l.weights[k] * probebake_backface_weight(normal, probebake_probes[probe].position - position);
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

// The stencil of p''s own leaf: the lookup of the light update's bounce (bake::svo_stencil).
ProbebakeStencil probebake_svo_stencil(vec3 position, vec3 normal) {
  return probebake_leaf_stencil(probebake_find_svo_leaf(position + normal * probebake_normal_bias()), position,
                                normal);
}

// Step 3: the leaves of the blend and their normalised weights (count 0: a miss).
struct ProbebakeBlend {
  int leaves[8];
  float weights[8];
  int count;
};

// Adds to the entry of the same leaf, else appends.
void probebake_blend_add(inout ProbebakeBlend b, int leaf, float weight) {
  for (int i = 0; i < b.count; ++i) {
    if (b.leaves[i] == leaf) {
      b.weights[i] += weight;
      return;
    }
  }
  b.leaves[b.count] = leaf;
  b.weights[b.count] = weight;
  ++b.count;
}

ProbebakeBlend probebake_blend_normalised(ProbebakeBlend b) {
  float sum = 0.0;
  for (int i = 0; i < b.count; ++i) sum += b.weights[i];
  for (int i = 0; i < b.count; ++i) b.weights[i] = b.weights[i] / sum;
  return b;
}

bool probebake_leaf_serves(int leaf, vec3 position, vec3 normal) {
  return leaf >= 0 && probebake_leaf_stencil(leaf, position, normal).probes.x >= 0;
}

// The leaf of largest weight (the first on ties), -1 when empty.
int probebake_blend_heaviest(ProbebakeBlend b) {
  int best = -1;
  float best_weight = 0.0;
  for (int i = 0; i < b.count; ++i) {
    if (b.weights[i] > best_weight) {
      best = b.leaves[i];
      best_weight = b.weights[i];
    }
  }
  return best;
}

bool probebake_leaves_share_a_probe(int a, int b) {
  const ivec4 pa = probebake_svo_leaves[a].probes, pb = probebake_svo_leaves[b].probes;
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k)
    for (int j = 0; j < SVO_PROBES_PER_LEAF; ++j)
      if (pa[k] >= 0 && pa[k] == pb[j]) return true;
  return false;
}

// The entries joined to leaf `root` by chains of leaves that share a probe, in their order: leaves across a
// wall or inside a sealed cavity hold other probes.
ProbebakeBlend probebake_blend_connected_to(ProbebakeBlend b, int root) {
  bool joined[8] = bool[8](false, false, false, false, false, false, false, false);
  for (bool grew = true; grew;) {
    grew = false;
    for (int i = 0; i < b.count; ++i) {
      if (joined[i]) continue;
      bool joins = b.leaves[i] == root || probebake_leaves_share_a_probe(b.leaves[i], root);
      for (int j = 0; j < b.count && !joins; ++j) joins = joined[j] && probebake_leaves_share_a_probe(b.leaves[i], b.leaves[j]);
      if (joins) {
        joined[i] = true;
        grew = true;
      }
    }
  }
  ProbebakeBlend kept;
  kept.count = 0;
  for (int i = 0; i < b.count; ++i)
    if (joined[i]) probebake_blend_add(kept, b.leaves[i], b.weights[i]);
  return kept;
}

ProbebakeBlend probebake_blended_lookup(vec3 position, vec3 normal) {
  ProbebakeBlend b;
  b.count = 0;
  const float bias = probebake_normal_bias();
  const vec3 biased = position + normal * bias;
  vec3 rel;
  if (!probebake_has_svo() || !probebake_root_relative(biased, rel)) return b;
  int depth;
  const int home = probebake_find_svo_leaf(biased, depth);
  const int n = 1 << probebake_info.svo_depth;
  const float voxel = probebake_info.root_size / float(n);
  // The eight finest voxel centres around p', clamped to the root cube (centres beyond it repeat the edge).
  const vec3 g = rel * float(n) - 0.5;
  const vec3 floor_g = floor(g);
  const vec3 f = g - floor_g;
  const ivec3 lo = clamp(ivec3(floor_g), ivec3(0), ivec3(n - 1));
  const ivec3 hi = clamp(ivec3(floor_g) + 1, ivec3(0), ivec3(n - 1));
  if (home >= 0) {
    // All eight centres inside p''s own leaf give that leaf's stencil whatever their weights: one descent.
    const int span = 1 << (probebake_info.svo_depth - depth);
    const ivec3 first = probebake_voxel_of(rel) / span * span;
    if (all(greaterThanEqual(lo, first)) && all(lessThan(hi, first + span))) {
      if (probebake_leaf_serves(home, position, normal)) probebake_blend_add(b, home, 1.0);
      return probebake_blend_normalised(b);
    }
  }
  for (int corner = 0; corner < 8; ++corner) {
    const bvec3 up = bvec3((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
    const ivec3 c = ivec3(up.x ? hi.x : lo.x, up.y ? hi.y : lo.y, up.z ? hi.z : lo.z);
    const vec3 t = vec3(up.x ? f.x : 1.0 - f.x, up.y ? f.y : 1.0 - f.y, up.z ? f.z : 1.0 - f.z);
    const vec3 centre = probebake_info.root_min + (vec3(c) + 0.5) * voxel;
    // Centres behind the surface's plane do not blend in: they may lie past a thin wall.
    const float side = clamp(dot(centre - position, normal) / bias, 0.0, 1.0);
    const float weight = t.x * t.y * t.z * side;
    if (!(weight > 0.0)) continue;
    int leaf_depth;
    const int leaf = probebake_leaf_of_voxel(c, leaf_depth);
    if (probebake_leaf_serves(leaf, position, normal)) probebake_blend_add(b, leaf, weight);
  }
  const int root = probebake_leaf_serves(home, position, normal) ? home : probebake_blend_heaviest(b);
  if (root < 0) return b;
  b = probebake_blend_connected_to(b, root);
  if (b.count == 0) probebake_blend_add(b, root, 1.0);
  return probebake_blend_normalised(b);
}

// Irradiance of probe `probe` at unit normal for basis values y, per channel, not clamped.
vec3 probebake_evaluate_probe_sh(int probe, float y[9]) {
  vec3 e = vec3(0.0);
  for (int k = 0; k < 9; ++k) {
    const vec3 c = vec3(probebake_probes[probe].irradiance_sh[3 * k], probebake_probes[probe].irradiance_sh[3 * k + 1],
                        probebake_probes[probe].irradiance_sh[3 * k + 2]);
    e += y[k] * c;
  }
  return e;
}

// Step 4.
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

// Step 4 over a blend.
vec3 probebake_apply_blend(ProbebakeBlend b, vec3 position, vec3 normal) {
  vec3 e = vec3(0.0);
  for (int i = 0; i < b.count; ++i)
    e += b.weights[i] * probebake_apply_stencil(probebake_leaf_stencil(b.leaves[i], position, normal), normal);
  return e;
}

vec3 probebake_sample_irradiance(vec3 position, vec3 normal) {
  return probebake_apply_blend(probebake_blended_lookup(position, normal), position, normal);
}

#ifdef PROBEBAKE_BINDING_RECORD_SLOTS
#if PROBEBAKE_DECLARE_BUFFERS
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_RECORD_SLOTS) readonly buffer ProbebakeRecordSlots {
  int probebake_record_slots[];
};
#endif

// A probe of the stencil has no record slot or is unresolved: the light update does not relight it.
bool probebake_stencil_not_lit(ProbebakeStencil s) {
  bool not_lit = false;
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
    if (s.probes[k] < 0) continue;
    const int slot = probebake_record_slots[s.probes[k]];
    not_lit = not_lit || slot < 0 || (slot & RECORD_SLOT_UNRESOLVED) != 0;
  }
  return not_lit;
}

bool probebake_blend_not_lit(ProbebakeBlend b, vec3 position, vec3 normal) {
  bool not_lit = false;
  for (int i = 0; i < b.count; ++i)
    not_lit = not_lit || probebake_stencil_not_lit(probebake_leaf_stencil(b.leaves[i], position, normal));
  return not_lit;
}

bool probebake_sample_irradiance_not_lit(vec3 position, vec3 normal, out vec3 irradiance) {
  const ProbebakeBlend b = probebake_blended_lookup(position, normal);
  irradiance = probebake_apply_blend(b, position, normal);
  return probebake_blend_not_lit(b, position, normal);
}
#endif

#endif // PROBEBAKE_SAMPLE_IRRADIANCE_GLSL
