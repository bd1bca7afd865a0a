// Irradiance lookup from a probebake volume in GLSL: include this in your own shader to sample the same
// storage buffers the runtime uploads (Volume::buffers() in runtime/include/probebake/runtime/runtime.h).
// It is the GPU twin of probe_index::sample_irradiance (probe_index/include/probebake/probe_index/lookup.h), step for step:
//   1. p' = position + normal * (half an SVO voxel); outside the root cube: a miss;
//   2. a leaf's stencil: up to four probes, stored weight * DDGI's smooth back-face weight, normalised;
//   3. the blend: the eight finest-voxel centres around p' look up their leaves (SVO descent), weighted
//      trilinearly and by the side of the surface's plane they lie on; only leaves joined to p''s own by
//      leaves sharing a probe stay; the result is continuous across leaf borders; one descent when all
//      eight lie in p''s own leaf;
//   4. each probe of the blend's leaves once, weighted by the sum over leaves of leaf weight * its stencil
//      weight there: sum of weight * max(0, probe SH irradiance).
//
// Requires: #version 450 or later, GL_GOOGLE_include_directive, include path shaders/include.
// Buffers (std430, read-only), declared here unless PROBEBAKE_DECLARE_BUFFERS is defined to 0, in which case
// the including shader declares the four names below itself (e.g. through buffer references):
//   PROBEBAKE_BINDING_VOLUME_INFO (default 0): VolumeInfo probebake_info        <- Volume::buffers().volume_info
//   PROBEBAKE_BINDING_PROBES      (default 1): Probe probebake_probes[]         <- .probes
//   PROBEBAKE_BINDING_SVO_NODES   (default 2): int probebake_svo_nodes[]        <- .svo_nodes
//   PROBEBAKE_BINDING_SVO_LEAVES  (default 3): SvoLeaf probebake_svo_leaves[]   <- .svo_leaves
// all in descriptor set PROBEBAKE_SET (default 0). Define the macros before the #include to move them (an
// integer literal or any GLSL constant expression); the defaults are the runtime's volume set (VOLUME_SET,
// VOLUME_BINDING_* of probebake/bindings.h), so a game may also bind that set as the runtime writes it.
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
// Defaults: the runtime's volume set (VOLUME_SET, VOLUME_BINDING_* 0-3 in bindings.h).
#ifndef PROBEBAKE_BINDING_VOLUME_INFO
#define PROBEBAKE_BINDING_VOLUME_INFO VOLUME_BINDING_VOLUME_INFO
#endif
#ifndef PROBEBAKE_BINDING_PROBES
#define PROBEBAKE_BINDING_PROBES VOLUME_BINDING_PROBES
#endif
#ifndef PROBEBAKE_BINDING_SVO_NODES
#define PROBEBAKE_BINDING_SVO_NODES VOLUME_BINDING_SVO_NODES
#endif
#ifndef PROBEBAKE_BINDING_SVO_LEAVES
#define PROBEBAKE_BINDING_SVO_LEAVES VOLUME_BINDING_SVO_LEAVES
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

// Compact probes (docs/RUNTIME.md "Compact probes"): with PROBEBAKE_PROBE_CODE_BANDS defined (1: the l1 code,
// 2: l2, 0: the records; a constant or any GLSL expression), the lookups read a probe's position from
// vec4 probebake_probe_points[] (<- Volume::buffers().probe_points; w = 0 for a free slot) and its irradiance
// from uvec4 probebake_probe_codes[] (<- .probe_codes, PROBEBAKE_PROBE_CODE_BANDS blocks per probe,
// probebake/sh_code.h) instead of its 144-byte record, which is then not read. Unless
// PROBEBAKE_DECLARE_BUFFERS is 0 they are declared at PROBEBAKE_BINDING_PROBE_POINTS and
// PROBEBAKE_BINDING_PROBE_CODES of PROBEBAKE_SET (no defaults).
#ifdef PROBEBAKE_PROBE_CODE_BANDS
#include "probebake/sh_code.h"
#if PROBEBAKE_DECLARE_BUFFERS
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_PROBE_POINTS) readonly buffer ProbebakeProbePoints {
  vec4 probebake_probe_points[];
};
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_PROBE_CODES) readonly buffer ProbebakeProbeCodes {
  uvec4 probebake_probe_codes[];
};
#endif
#endif

vec3 probebake_probe_position(int probe) {
#ifdef PROBEBAKE_PROBE_CODE_BANDS
  if (PROBEBAKE_PROBE_CODE_BANDS != 0) return probebake_probe_points[probe].xyz;
#endif
  return probebake_probes[probe].position; // not the whole 144-byte record
}

// Whether slot `probe` holds an allocated probe.
bool probebake_probe_live(int probe) {
#ifdef PROBEBAKE_PROBE_CODE_BANDS
  if (PROBEBAKE_PROBE_CODE_BANDS != 0) return probebake_probe_points[probe].w != 0.0;
#endif
  return probebake_probes[probe].link != 0;
}

// Irradiance of probe `probe` at unit normal for basis values y, per channel, not clamped.
vec3 probebake_evaluate_probe_sh(int probe, float y[9]) {
  vec3 e = vec3(0.0);
#ifdef PROBEBAKE_PROBE_CODE_BANDS
  const int bands = PROBEBAKE_PROBE_CODE_BANDS;
  if (bands != 0) {
    const ShCode code = ShCode(probebake_probe_codes[bands * probe],
                               bands == 2 ? probebake_probe_codes[bands * probe + 1] : uvec4(0u));
    const vec3 l0 = sh_code_l0(code.band01);
    // Constant bounds: unrolled, every bit position is a constant (an L1 code's zero block decodes to 0).
    for (int k = 0; k < 9; ++k)
      e += y[k] * vec3(sh_code_coefficient(code, l0, 3 * k), sh_code_coefficient(code, l0, 3 * k + 1),
                       sh_code_coefficient(code, l0, 3 * k + 2));
    return e;
  }
#endif
  for (int k = 0; k < 9; ++k) {
    const vec3 c = vec3(probebake_probes[probe].irradiance_sh[3 * k], probebake_probes[probe].irradiance_sh[3 * k + 1],
                        probebake_probes[probe].irradiance_sh[3 * k + 2]);
    e += y[k] * c;
  }
  return e;
}

#include "probebake/svo_stencil.glsl"

// Step 3: the leaves of the blend and their normalised weights (count 0: a miss). Leaves are read again
// where needed: keeping their payloads here doubled the H200's time per lookup (local memory).
struct ProbebakeBlend {
  int leaves[8];
  float weights[8];
  int count;
};

// Adds to the entry of the same leaf, else appends it.
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

// The payload holds a probe in range with a positive stored weight (its stencil is then not empty).
bool probebake_payload_serves(SvoLeaf l) {
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k)
    if (l.probes[k] >= 0 && l.probes[k] < probebake_info.probe_capacity && l.weights[k] > 0.0) return true;
  return false;
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

bool probebake_probes_share(ivec4 pa, ivec4 pb) {
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k)
    for (int j = 0; j < SVO_PROBES_PER_LEAF; ++j)
      if (pa[k] >= 0 && pa[k] == pb[j]) return true;
  return false;
}

// The entries joined to leaf `root` by chains of leaves that share a probe, in their order: leaves across a
// wall or inside a sealed cavity hold other probes.
ProbebakeBlend probebake_blend_connected_to(ProbebakeBlend b, int root) {
  const ivec4 root_probes = probebake_svo_leaves[root].probes;
  bool joined[8] = bool[8](false, false, false, false, false, false, false, false);
  for (bool grew = true; grew;) {
    grew = false;
    for (int i = 0; i < b.count; ++i) {
      if (joined[i]) continue;
      const ivec4 probes = probebake_svo_leaves[b.leaves[i]].probes;
      bool joins = b.leaves[i] == root || probebake_probes_share(probes, root_probes);
      for (int j = 0; j < b.count && !joins; ++j)
        joins = joined[j] && probebake_probes_share(probes, probebake_svo_leaves[b.leaves[j]].probes);
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
  const int n = 1 << probebake_info.svo_depth;
  const float voxel = probebake_info.root_size / float(n);
  // The eight finest voxel centres around p', clamped to the root cube (centres beyond it repeat the edge).
  const vec3 g = rel * float(n) - 0.5;
  const vec3 floor_g = floor(g);
  const vec3 f = g - floor_g;
  const ivec3 lo = clamp(ivec3(floor_g), ivec3(0), ivec3(n - 1));
  const ivec3 hi = clamp(ivec3(floor_g) + 1, ivec3(0), ivec3(n - 1));
  // The corners share the bits above the highest one in which lo and hi differ: one walk down to there.
  const ivec3 differ = lo ^ hi;
  const int spread = findMSB(differ.x | differ.y | differ.z) + 1;
  const ProbebakeWalk top = probebake_walk(ProbebakeWalk(0, probebake_info.svo_depth - 1, false, -1), lo, spread);
  const ProbebakeWalk next = probebake_walk(top, lo, top.level); // one level more: a leaf there holds every corner
  if (top.ended || next.ended) {
    const int leaf = top.ended ? top.leaf : next.leaf;
    if (leaf >= 0 && probebake_payload_serves(probebake_svo_leaves[leaf])) probebake_blend_add(b, leaf, 1.0);
    return probebake_blend_normalised(b);
  }
  // p''s own voxel is one of the corners.
  const ivec3 own = probebake_voxel_of(rel);
  int home = -1;
  bool home_serves = false;
  for (int corner = 0; corner < 8; ++corner) {
    const bvec3 up = bvec3((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
    const ivec3 c = ivec3(up.x ? hi.x : lo.x, up.y ? hi.y : lo.y, up.z ? hi.z : lo.z);
    const vec3 t = vec3(up.x ? f.x : 1.0 - f.x, up.y ? f.y : 1.0 - f.y, up.z ? f.z : 1.0 - f.z);
    const vec3 centre = probebake_info.root_min + (vec3(c) + 0.5) * voxel;
    // Centres behind the surface's plane do not blend in: they may lie past a thin wall.
    const float side = clamp(dot(centre - position, normal) / bias, 0.0, 1.0);
    const float weight = t.x * t.y * t.z * side;
    const bool is_own = c == own && home < 0;
    if (!(weight > 0.0) && !is_own) continue;
    const int leaf = probebake_walk(top, c, -1).leaf;
    if (leaf < 0) continue;
    const bool serves = probebake_payload_serves(probebake_svo_leaves[leaf]);
    if (is_own) {
      home = leaf;
      home_serves = serves;
    }
    if (weight > 0.0 && serves) probebake_blend_add(b, leaf, weight);
  }
  const int root = home_serves ? home : probebake_blend_heaviest(b);
  if (root < 0) return b;
  b = probebake_blend_connected_to(b, root);
  if (b.count == 0) probebake_blend_add(b, root, 1.0);
  return probebake_blend_normalised(b);
}

// Step 4's weights: each probe of the blend's leaves once (first-read order), weight = sum over leaves of
// leaf weight * the probe's normalised stencil weight there; its back-face weight computed once.
struct ProbebakeProbeBlend {
  int probes[8 * SVO_PROBES_PER_LEAF];
  float weights[8 * SVO_PROBES_PER_LEAF];
  int count;
};

ProbebakeProbeBlend probebake_probe_blend(ProbebakeBlend b, vec3 position, vec3 normal) {
  ProbebakeProbeBlend out_blend;
  out_blend.count = 0;
  float backface[8 * SVO_PROBES_PER_LEAF];
  for (int i = 0; i < b.count; ++i) {
    const SvoLeaf l = probebake_svo_leaves[b.leaves[i]];
    ivec4 slot = ivec4(-1);
    vec4 w = vec4(0.0);
    float sum = 0.0;
    for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
      const int probe = l.probes[k];
      if (probe < 0 || probe >= probebake_info.probe_capacity) continue;
      int j = 0;
      while (j < out_blend.count && out_blend.probes[j] != probe) ++j;
      if (j == out_blend.count) {
        out_blend.probes[j] = probe;
        out_blend.weights[j] = 0.0;
        backface[j] = probebake_backface_weight(normal, probebake_probe_position(probe) - position);
        ++out_blend.count;
      }
      slot[k] = j;
      w[k] = l.weights[k] * backface[j];
      sum += w[k];
    }
    if (!(sum > 0.0)) continue;
    for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k)
      if (slot[k] >= 0) out_blend.weights[slot[k]] += b.weights[i] * (w[k] / sum);
  }
  return out_blend;
}

// E = sum_j weight_j * max(0, E_j(normal)).
vec3 probebake_apply_probe_blend(ProbebakeProbeBlend p, vec3 normal) {
  vec3 e = vec3(0.0);
  if (p.count == 0) return e;
  float y[9];
  probebake_sh_basis(normal, y);
  for (int j = 0; j < p.count; ++j) e += p.weights[j] * max(probebake_evaluate_probe_sh(p.probes[j], y), vec3(0.0));
  return e;
}

vec3 probebake_sample_irradiance(vec3 position, vec3 normal) {
  return probebake_apply_probe_blend(probebake_probe_blend(probebake_blended_lookup(position, normal), position, normal),
                                     normal);
}

#ifdef PROBEBAKE_BINDING_RECORD_SLOTS
#if PROBEBAKE_DECLARE_BUFFERS
layout(std430, set = PROBEBAKE_SET, binding = PROBEBAKE_BINDING_RECORD_SLOTS) readonly buffer ProbebakeRecordSlots {
  int probebake_record_slots[];
};
#endif

// A probe of the blend has no record slot or is unresolved: the light update does not relight it.
bool probebake_probe_blend_not_lit(ProbebakeProbeBlend p) {
  bool not_lit = false;
  for (int j = 0; j < p.count; ++j) {
    const int slot = probebake_record_slots[p.probes[j]];
    not_lit = not_lit || slot < 0 || (slot & RECORD_SLOT_UNRESOLVED) != 0;
  }
  return not_lit;
}

bool probebake_sample_irradiance_not_lit(vec3 position, vec3 normal, out vec3 irradiance) {
  const ProbebakeProbeBlend p = probebake_probe_blend(probebake_blended_lookup(position, normal), position, normal);
  irradiance = probebake_apply_probe_blend(p, normal);
  return probebake_probe_blend_not_lit(p);
}
#endif

#endif // PROBEBAKE_SAMPLE_IRRADIANCE_GLSL
