// The grid engine's sampling pass: one query per invocation through the GLSL include a game uses
// (probebake/sample_grid.glsl), the lattice in set 1 (sample_bindings.h), and the compact probes when the volume
// has them (sample_codes.glsl).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/volume_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "sampling/sample_bindings.h"
#define PROBEBAKE_GRID_SET PASS_SET
#define PROBEBAKE_BINDING_GRID_LATTICE SAMPLE_GRID_BINDING_LATTICE
layout(push_constant) uniform Push { SamplePush push; };
#define POINTS_BINDING SAMPLE_GRID_BINDING_PROBE_POINTS
#define CODES_BINDING SAMPLE_GRID_BINDING_PROBE_CODES
#include "sampling/sample_codes.glsl"
#include "probebake/sample_grid.glsl"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(std430, set = PASS_SET, binding = SAMPLE_GRID_BINDING_QUERIES) readonly buffer Queries { SampleQuery queries[]; };
layout(std430, set = PASS_SET, binding = SAMPLE_GRID_BINDING_RESULTS) writeonly buffer Results { SampleResult results[]; };

void main() {
  const uint i = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  if (i >= push.count) return;
  const SampleQuery q = queries[i];
  int corners;
  const vec3 e = probebake_sample_irradiance_grid(q.position, q.normal, corners);
  results[i] = SampleResult(e, corners);
}
