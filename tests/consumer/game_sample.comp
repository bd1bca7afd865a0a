// A game's own compute shader sampling probebake's irradiance (docs/RUNTIME.md "How a game samples the
// volume"), with the volume's buffers moved to set 1, bindings 4-7, as an engine with its own layout would.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_SET 1
#define PROBEBAKE_BINDING_VOLUME_INFO 4
#define PROBEBAKE_BINDING_PROBES 5
#define PROBEBAKE_BINDING_SVO_NODES 6
#define PROBEBAKE_BINDING_SVO_LEAVES 7
#include "probebake/sample_irradiance.glsl"

layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Points { vec4 points[]; };  // xyz position
layout(std430, set = 0, binding = 1) readonly buffer Normals { vec4 normals[]; }; // xyz unit normal
layout(std430, set = 0, binding = 2) writeonly buffer Shaded { vec4 shaded[]; };  // xyz irradiance
layout(push_constant) uniform Push { uint count; } push;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= push.count) return;
  shaded[i] = vec4(probebake_sample_irradiance(points[i].xyz, normals[i].xyz), 1.0);
}
