// Dynamic objects (docs/RUNTIME_INTERNALS.md "Moving objects: internals"): one thread per object derives,
// from the pose the host wrote (ObjectInstance::world_from_object), the inverse that rays enter the object
// with and the world box of the object box's 8 corners that bvh_trace.glsl tests first. The box is padded by
// a relative 1e-5 (and 1e-6 m) so that rounding of the transformed corners never culls a triangle in a box
// face.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_WRITES_INSTANCES
#include "probebake/volume_bindings.glsl"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(push_constant) uniform Push { ObjectRefitPush push; };

void main() {
  const uint o = gl_GlobalInvocationID.x;
  if (o >= push.objects) return;
  const vec4 r0 = probebake_object_instances[o].world_from_object[0], r1 = probebake_object_instances[o].world_from_object[1],
             r2 = probebake_object_instances[o].world_from_object[2];
  const mat3 linear = transpose(mat3(r0.xyz, r1.xyz, r2.xyz)); // GLSL matrices are built from columns
  const mat3 inv = inverse(linear);
  const vec3 inv_t = -(inv * vec3(r0.w, r1.w, r2.w));
  const mat3 rows = transpose(inv); // rows[k] = row k of the inverse
  probebake_object_instances[o].object_from_world[0] = vec4(rows[0], inv_t.x);
  probebake_object_instances[o].object_from_world[1] = vec4(rows[1], inv_t.y);
  probebake_object_instances[o].object_from_world[2] = vec4(rows[2], inv_t.z);
  const vec3 lower = probebake_dynamic_objects[o].lower, upper = probebake_dynamic_objects[o].upper;
  vec3 lo = vec3(3.4e38), hi = vec3(-3.4e38);
  for (int c = 0; c < 8; ++c) {
    const vec4 p = vec4((c & 1) != 0 ? upper.x : lower.x, (c & 2) != 0 ? upper.y : lower.y, (c & 4) != 0 ? upper.z : lower.z, 1.0);
    const vec3 w = vec3(dot(r0, p), dot(r1, p), dot(r2, p));
    lo = min(lo, w);
    hi = max(hi, w);
  }
  const vec3 pad = vec3(1e-5 * max(max(hi.x - lo.x, hi.y - lo.y), hi.z - lo.z) + 1e-6) + 1e-6 * max(abs(lo), abs(hi));
  probebake_object_instances[o].world_lower = lo - pad;
  probebake_object_instances[o].world_upper = hi + pad;
  probebake_object_instances[o].pad0 = 0.0;
  probebake_object_instances[o].pad1 = 0.0;
}
