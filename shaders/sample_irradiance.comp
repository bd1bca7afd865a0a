// Irradiance sampling pass: one query (position, normal) per invocation, through the same GLSL include a
// game uses (probebake/sample_irradiance.glsl at its default bindings); queries and results at the
// SAMPLE_BINDING_* of probebake/bindings.h.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/bindings.h"
#include "probebake/runtime_types.h"
#include "probebake/dispatch.glsl"
#define PROBEBAKE_BINDING_RECORD_SLOTS SAMPLE_BINDING_RECORD_SLOTS // read only when push.streaming
#include "probebake/sample_irradiance.glsl"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = SAMPLE_BINDING_QUERIES) readonly buffer Queries { SampleQuery queries[]; };
layout(std430, set = 0, binding = SAMPLE_BINDING_RESULTS) writeonly buffer Results { SampleResult results[]; };
layout(push_constant) uniform Push { SamplePush push; };

void main() {
  const uint i = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  if (i >= push.count) return;
  const SampleQuery q = queries[i];
  const ProbebakeBlend b = probebake_blended_lookup(q.position, q.normal);
  int used = 0;
  for (int l = 0; l < b.count; ++l) {
    const ProbebakeStencil s = probebake_leaf_stencil(b.leaves[l], q.position, q.normal);
    for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) used += s.probes[k] >= 0 ? 1 : 0;
  }
  const bool not_lit = push.streaming != 0u && probebake_blend_not_lit(b, q.position, q.normal);
  results[i] = SampleResult(probebake_apply_blend(b, q.position, q.normal), used | (not_lit ? SAMPLE_RESULT_NOT_LIT : 0));
}
