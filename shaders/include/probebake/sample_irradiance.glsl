// Irradiance lookup from a probebake volume in GLSL: include this in your own shader to sample the same
// storage buffers the runtime uploads (Volume::buffers() in runtime/include/probebake/runtime/runtime.h).
// It is the GPU twin of bake::sample_irradiance (bake/include/probebake/bake/sampler.h), step for step:
//   1. p' = position + normal * (half an SVO voxel);
//   2. SVO descent to the leaf holding p' (miss: empty node or p' outside the root cube);
//   3. up to four probes, stored weight * DDGI's smooth back-face weight, normalised;
//   4. sum of weight * max(0, probe SH irradiance at the normal).
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

// Step 2: index into probebake_svo_leaves of the leaf containing p, or -1.
int probebake_find_svo_leaf(vec3 p) {
  const int depth = probebake_info.svo_depth;
  if (probebake_info.svo_nodes <= 0 || depth < 0 || depth > 30) return -1;
  const vec3 t = (p - probebake_info.root_min) / probebake_info.root_size;
  if (!(t.x >= 0.0 && t.y >= 0.0 && t.z >= 0.0 && t.x <= 1.0 && t.y <= 1.0 && t.z <= 1.0)) return -1;
  const int n = 1 << depth;
  const ivec3 c = clamp(ivec3(floor(t * float(n))), ivec3(0), ivec3(n - 1));
  int node = 0;
  for (int level = depth - 1; level >= -1; --level) {
    const int v = probebake_svo_nodes[node];
    if (v < 0) return ~v < probebake_info.svo_leaves ? ~v : -1;
    if (v == 0 || level < 0) return -1;
    const int octant = ((c.x >> level) & 1) | (((c.y >> level) & 1) << 1) | (((c.z >> level) & 1) << 2);
    if (v > probebake_info.svo_nodes - 1 - octant) return -1; // v + octant >= svo_nodes, without overflow
    node = v + octant;
  }
  return -1;
}

// ((dot(n, dir) + 1) / 2)^2 + 0.05, dir towards the probe from the shaded point (zero on the probe).
float probebake_backface_weight(vec3 normal, vec3 to_probe) {
  const vec3 dir = to_probe * (1.0 / sqrt(max(dot(to_probe, to_probe), 1e-30)));
  const float c = 0.5 * (dot(normal, dir) + 1.0);
  return c * c + 0.05;
}

// Steps 1-3.
ProbebakeStencil probebake_svo_stencil(vec3 position, vec3 normal) {
  ProbebakeStencil s = ProbebakeStencil(ivec4(-1), vec4(0.0));
  const int leaf = probebake_find_svo_leaf(position + normal * probebake_normal_bias());
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

vec3 probebake_sample_irradiance(vec3 position, vec3 normal) {
  return probebake_apply_stencil(probebake_svo_stencil(position, normal), normal);
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

bool probebake_sample_irradiance_not_lit(vec3 position, vec3 normal, out vec3 irradiance) {
  const ProbebakeStencil s = probebake_svo_stencil(position, normal);
  irradiance = probebake_apply_stencil(s, normal);
  return probebake_stencil_not_lit(s);
}
#endif

#endif // PROBEBAKE_SAMPLE_IRRADIANCE_GLSL
