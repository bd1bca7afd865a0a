// Streamed tracing arena compaction (docs/RUNTIME_INTERNALS.md "Streaming cells: internals"): one cell's
// block moves from `from_byte` to `to_byte`. The host copied the block into the scratch buffer and copies its
// vertices back itself; one thread per inner node or face writes it at the new place, its indices shifted by
// the move (offsets are multiples of 96, so the byte distance is a whole number of nodes, faces and
// vertices).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/dispatch.glsl"
#include "probebake/gpu_types.h"
#include "probebake/runtime_types.h"
#include "streaming/stream_bindings.h"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

layout(std430, set = PASS_SET, binding = STREAM_BINDING_ARENA) writeonly buffer ArenaBuffer { uint arena[]; };
layout(std430, set = PASS_SET, binding = STREAM_BINDING_SCRATCH) readonly buffer ScratchBuffer { uint scratch[]; };
layout(push_constant) uniform Push { StreamRelocatePush push; };

// A child word moved: a leaf's first face, or an inner node's index, shifted.
uint moved_word(uint word, int node_shift, int face_shift) {
  if ((word & TRACE_CHILD_LEAF) != 0u)
    return (word & ~TRACE_LEAF_FIRST_MASK) | uint(int(word & TRACE_LEAF_FIRST_MASK) + face_shift);
  return uint(int(word) + node_shift);
}

void main() {
  const uint i = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  if (i >= push.nodes + push.faces) return;
  const int distance = int(push.to_byte) - int(push.from_byte);
  const uint to = push.to_byte / 4u;
  if (i < push.nodes) { // TraceNode: 6 box words, then 2 child words
    const uint at = 8u * i;
    for (uint w = 0u; w < 6u; ++w) arena[to + at + w] = scratch[at + w];
    for (uint w = 6u; w < 8u; ++w) arena[to + at + w] = moved_word(scratch[at + w], distance / 32, distance / 16);
    return;
  }
  const uint at = 8u * push.nodes + 4u * (i - push.nodes); // TraceFace: 3 vertex indices, then the material
  for (uint w = 0u; w < 3u; ++w) arena[to + at + w] = uint(int(scratch[at + w]) + distance / 12);
  arena[to + at + 3u] = scratch[at + 3u];
}
