// The compact probes a game looks up (probebake/sh_code.h): every probe slot's point and code from its
// record, one slot per invocation, after the frame's light update has written the records.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/volume_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/sh_code.h"
#include "probe_codes/probe_codes_bindings.h"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(std430, set = PASS_SET, binding = PROBE_CODES_BINDING_POINTS) writeonly buffer Points { vec4 points[]; };
layout(std430, set = PASS_SET, binding = PROBE_CODES_BINDING_CODES) writeonly buffer Codes { uvec4 codes[]; };
layout(push_constant) uniform Push { ProbeCodePush push; };

void main() {
  const uint i = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  if (i >= push.probe_capacity) return;
  const bool live = probebake_probes[i].link != 0;
  float sh[27];
  for (int j = 0; j < 27; ++j) sh[j] = live ? probebake_probes[i].irradiance_sh[j] : 0.0;
  const ShCode code = sh_code_encode(sh, push.code_bands == 2u);
  points[i] = live ? vec4(probebake_probes[i].position, 1.0) : vec4(0.0);
  codes[push.code_bands * i] = code.band01;
  if (push.code_bands == 2u) codes[2u * i + 1u] = code.band2;
}
