// Light update, before L1: one thread per list place (or window index without a list) appends the slots of
// the probes that trace this frame (light_trace_slot) to the light list's trace slots and raises
// light_trace's indirect dispatch to cover them (from the zeros the host filled in). light_trace then runs
// LIGHT_TRACE_CHUNKS workgroups for each probe that traces, not for every listed probe: a frame where
// nothing traces dispatches nothing. The slots' order follows the threads; each probe's trace is its own.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_LIGHT_LIST_WRITABLE
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

void main() {
  const uint place = probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex;
  const int slot = light_trace_slot(place);
  if (slot < 0) return;
  const uint i = atomicAdd(light_list_header.trace_count, 1u);
  light_list[push.probe_capacity + i] = slot;
  const uint groups = i + 1u; // as memory_begin folds the list's sizes: x up to LIGHT_LIST_MAX_GROUPS_X, then y
  atomicMax(light_list_header.trace_x, min(groups, LIGHT_LIST_MAX_GROUPS_X));
  atomicMax(light_list_header.trace_y, (groups + LIGHT_LIST_MAX_GROUPS_X - 1u) / LIGHT_LIST_MAX_GROUPS_X);
  atomicMax(light_list_header.trace_z, LIGHT_TRACE_CHUNKS);
}
