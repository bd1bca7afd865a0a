// Memory update / light transitions, one-thread steps: push.phase 0 moves the pull origin (p <- p + 2 mod 3)
// and takes the memory update's segment p, with the dispatch sizes of its per-entry steps; phase 1 takes the light update's segment p + 1 (after the memory
// update pushed into it) and empties the light list; phase 2 (after memory_light) turns the list's count into
// the indirect dispatch sizes of light_gather and light_resolve (light_trace_list sizes light_trace). Taking = remembering the count
// and emptying the segment; the per-entry dispatches read the entries and clear their keys.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { MemoryPush push; };

// VkDispatchIndirectCommand for `groups` workgroups, folded into y (shaders use probebake_flat_workgroup()).
uvec3 folded(uint groups) {
  const uint x = min(groups, LIGHT_LIST_MAX_GROUPS_X);
  return uvec3(x, x == 0u ? 0u : (groups + x - 1u) / x, 1u);
}

void main() {
  if (push.phase == 0) {
    leaf_header.pull_origin = (leaf_header.pull_origin + 2) % 3;
    const int s = memory_pull_segment();
    memory_state.memory_segment = s;
    const int pulled = min(leaf_header.count[s], queue_capacity());
    memory_state.memory_pulled = pulled;
    leaf_header.count[s] = 0;
    const uvec3 g = folded(uint(pulled)), t = folded((uint(pulled) + MEMORY_WORKGROUP_SIZE - 1u) / MEMORY_WORKGROUP_SIZE);
    memory_state.entry_groups = uint[3](g.x, g.y, g.z);
    memory_state.entry_thread_groups = uint[3](t.x, t.y, t.z);
  } else if (push.phase == 2) {
    const uint count = light_list_header.count;
    const uvec3 g = folded(count), r = folded((count + RUNTIME_WORKGROUP_SIZE - 1u) / RUNTIME_WORKGROUP_SIZE);
    light_list_header.groups_x = g.x;
    light_list_header.groups_y = g.y;
    light_list_header.groups_z = g.z;
    light_list_header.resolve_x = r.x;
    light_list_header.resolve_y = r.y;
    light_list_header.resolve_z = r.z;
  } else {
    light_list_header.count = 0u;
    const int s = light_pull_segment();
    memory_state.light_segment = s;
    const int pulled = min(leaf_header.count[s], queue_capacity());
    memory_state.light_pulled = pulled;
    memory_state.traced = 0;
    const uvec3 g = folded(uint(pulled));
    memory_state.light_groups = uint[3](g.x, g.y, g.z);
    leaf_header.count[s] = 0;
  }
}
