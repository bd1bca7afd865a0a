// Light update without the memory update, frames in which objects moved: flags for re-tracing
// (TRACE_FLAG_RETRACE) the live probes whose rays may meet what moved, so that light_trace re-traces those
// and the others keep their records. A lighting ray can only change where its segment, from the probe to its
// record's hit (no end for a miss or a back-face record), crosses a box swept by a moving object
// (RelightChanges.boxes: each the union of an object's old and new world box); a lattice ray of an octree
// probe (its hit fraction) where the ray from its node's centre does. Boxes are padded by a relative 1e-4
// and slab tests are conservative, so a flagged-for-nothing probe costs a re-trace and a missed one cannot
// happen. light_relight recomputes, in the same frame, the punctual sums whose shadow rays may cross a box.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/octree.glsl"

layout(local_size_x = LIGHT_WORKGROUP_SIZE) in;

bool meets_moved(vec3 origin, vec3 dir, float t_max) {
  const uint count = min(relight_changes.moved_boxes, RELIGHT_MAX_MOVED_BOXES);
  for (uint b = 0u; b < count; ++b)
    if (segment_meets_box(origin, dir, t_max, relight_changes.boxes[b])) return true;
  return false;
}

void main() {
  const uint slot = probebake_flat_workgroup();
  // A probe without records yet traces them afresh when the load trace reaches it.
  if (slot >= push.probe_capacity || light_slot_idle(slot) || light_slot_untraced(slot)) return; // uniform
  const vec3 origin = probebake_probes[slot].position;
  bool meets = false;
  for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.rays && !meets; r += int(LIGHT_WORKGROUP_SIZE)) {
    const LightRecord rec = light_record(slot, uint(r));
    const vec3 dir = probebake_ray_directions[r].xyz;
    const float t_max = rec.kind == LIGHT_RECORD_FRONT ? length(rec.position - origin) * 1.0001 + 1e-6 : 3.4e38;
    meets = meets_moved(origin, dir, t_max);
  }
  const int node = probebake_probes[slot].node;
  if (node >= 0 && !meets) {
    vec3 cube_min;
    float size;
    int depth;
    octree_node_cube(node, cube_min, size, depth);
    const vec3 centre = cube_min + vec3(0.5 * size);
    for (int r = int(gl_LocalInvocationIndex); r < probebake_lighting.placement_rays && !meets; r += int(LIGHT_WORKGROUP_SIZE))
      meets = meets_moved(centre, probebake_ray_directions[probebake_lighting.rays + r].xyz, 3.4e38);
  }
  if (meets) atomicOr(trace_flags[slot], TRACE_FLAG_RETRACE);
}
