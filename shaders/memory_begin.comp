// Memory update / light transitions, one-thread steps: push.phase 0 moves the pull origin (p <- p + 2 mod 3)
// and takes the memory update's segment p; phase 1 takes the light update's segment p + 1 (after the memory
// update pushed into it) and empties the light list; phase 2 (after memory_light) turns the list's count into
// the indirect dispatch sizes of light_trace, light_gather and light_resolve. Taking = remembering the count
// and emptying the segment; the per-entry dispatches read the entries and clear their keys.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/memory_bindings.glsl"
#include "probebake/memory_update.glsl"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { MemoryPush push; };

void main() {
  if (push.phase == 0) {
    leaf_header.pull_origin = (leaf_header.pull_origin + 2) % 3;
    const int s = memory_pull_segment();
    memory_state.memory_segment = s;
    memory_state.memory_pulled = min(leaf_header.count[s], queue_capacity());
    leaf_header.count[s] = 0;
  } else if (push.phase == 2) {
    const uint count = light_list_header.count;
    const uint x = min(count, LIGHT_LIST_MAX_GROUPS_X);
    light_list_header.groups_x = x;
    light_list_header.groups_y = x == 0u ? 0u : (count + x - 1u) / x;
    light_list_header.groups_z = 1u;
    const uint groups = (count + RUNTIME_WORKGROUP_SIZE - 1u) / RUNTIME_WORKGROUP_SIZE;
    const uint rx = min(groups, LIGHT_LIST_MAX_GROUPS_X);
    light_list_header.resolve_x = rx;
    light_list_header.resolve_y = rx == 0u ? 0u : (groups + rx - 1u) / rx;
    light_list_header.resolve_z = 1u;
  } else {
    light_list_header.count = 0u;
    const int s = light_pull_segment();
    memory_state.light_segment = s;
    memory_state.light_pulled = min(leaf_header.count[s], queue_capacity());
    memory_state.traced = 0;
    leaf_header.count[s] = 0;
  }
}
