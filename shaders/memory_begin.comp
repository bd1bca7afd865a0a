// Memory update / light transitions, first step (one thread): push.phase 0 moves the pull origin
// (p <- p + 2 mod 3) and takes the memory update's segment p; phase 1 takes the light update's segment
// p + 1 (after the memory update pushed into it). Taking = remembering the count and emptying the segment;
// the per-entry dispatches read the entries and clear their keys.
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
  } else {
    const int s = light_pull_segment();
    memory_state.light_segment = s;
    memory_state.light_pulled = min(leaf_header.count[s], queue_capacity());
    memory_state.traced = 0;
    leaf_header.count[s] = 0;
  }
}
