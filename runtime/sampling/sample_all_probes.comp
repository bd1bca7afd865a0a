// The octree thesis's shading baseline (§3.2.4): every probe in the probe index list, one visibility ray
// through the BVH per probe, weight = DDGI back-face weight / max(d^2, bias^2). The GPU twin of
// probe_index::sample_irradiance_all_probes; kept only to measure the SVO sampler against it (probebake run
// --compare-all-probes), O(probes) rays per lookup where the SVO sampler reads one leaf.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/volume_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "sampling/sample_bindings.h"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(std430, set = PASS_SET, binding = SAMPLE_ALL_BINDING_QUERIES) readonly buffer Queries { SampleQuery queries[]; };
layout(std430, set = PASS_SET, binding = SAMPLE_ALL_BINDING_RESULTS) writeonly buffer Results { SampleResult results[]; };
layout(push_constant) uniform Push { SamplePush push; };

#include "probebake/sample_irradiance.glsl"
#include "probebake/bvh_trace.glsl"

void main() {
  const uint i = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  if (i >= push.count) return;
  const SampleQuery q = queries[i];
  const float bias = probebake_normal_bias();
  const vec3 biased = q.position + q.normal * bias;
  float y[9];
  probebake_sh_basis(q.normal, y);
  vec3 sum = vec3(0.0);
  float total = 0.0;
  int used = 0;
  for (int k = 0; k < probebake_info.probe_capacity; ++k) {
    const int probe = probe_index[k];
    if (probe < 0) break; // PROBE_INDEX_END
    const vec3 to = probebake_probes[probe].position - biased;
    const float dist = length(to);
    if (dist > 0.0 && probebake_occluded(biased, to / dist, 0.0, dist)) continue;
    const vec3 d = probebake_probes[probe].position - q.position;
    const float w = probebake_backface_weight(q.normal, d) / max(dot(d, d), bias * bias);
    sum += w * max(probebake_evaluate_probe_sh(probe, y), vec3(0.0));
    total += w;
    ++used;
  }
  results[i] = SampleResult(total > 0.0 ? sum / total : vec3(0.0), used);
}
