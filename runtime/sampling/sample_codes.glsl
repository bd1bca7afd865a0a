// The sampling kernels' compact probes (SamplePush.code_bands, probe_codes/): the points and codes in set 1,
// read by probebake/sample_irradiance.glsl's probe accessors when push.code_bands != 0. Include after the
// push constants and before probebake/sample_irradiance.glsl, with POINTS_BINDING and CODES_BINDING defined.
layout(std430, set = PASS_SET, binding = POINTS_BINDING) readonly buffer ProbePoints { vec4 probebake_probe_points[]; };
layout(std430, set = PASS_SET, binding = CODES_BINDING) readonly buffer ProbeCodes { uvec4 probebake_probe_codes[]; };
#define PROBEBAKE_PROBE_CODE_BANDS int(push.code_bands)
