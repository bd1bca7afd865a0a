// Irradiance sampling pass: one query (position, normal) per invocation, through the same GLSL include a
// game uses (probebake/sample_irradiance.glsl on the volume set); queries, results and the record slots in
// set 1 (sample_bindings.h), and the compact probes when the volume has them (sample_codes.glsl).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/volume_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "sampling/sample_bindings.h"
layout(std430, set = PASS_SET, binding = SAMPLE_BINDING_RECORD_SLOTS) readonly buffer RecordSlots {
  int probebake_record_slots[]; // read only when push.streaming
};
#define PROBEBAKE_BINDING_RECORD_SLOTS SAMPLE_BINDING_RECORD_SLOTS
layout(push_constant) uniform Push { SamplePush push; };
#define POINTS_BINDING SAMPLE_BINDING_PROBE_POINTS
#define CODES_BINDING SAMPLE_BINDING_PROBE_CODES
#include "sampling/sample_codes.glsl"
#include "probebake/sample_irradiance.glsl"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(std430, set = PASS_SET, binding = SAMPLE_BINDING_QUERIES) readonly buffer Queries { SampleQuery queries[]; };
layout(std430, set = PASS_SET, binding = SAMPLE_BINDING_RESULTS) writeonly buffer Results { SampleResult results[]; };

void main() {
  const uint i = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  if (i >= push.count) return;
  const SampleQuery q = queries[i];
  const ProbebakeProbeBlend p = probebake_probe_blend(probebake_blended_lookup(q.position, q.normal), q.position, q.normal);
  const bool not_lit = push.streaming != 0u && probebake_probe_blend_not_lit(p);
  results[i] = SampleResult(probebake_apply_probe_blend(p, q.normal), p.count | (not_lit ? SAMPLE_RESULT_NOT_LIT : 0));
}
