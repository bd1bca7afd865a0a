// Light update, end of L2 and L3 (octree thesis §3.2.2): one thread per probe slot (or listed probe). Copies the gathered
// irradiance (at the probe's record slot) into the probe, and judges the node by the leaf rule (probebake/leaf_rule.h). The tree is
// static in this version: L3 only counts the leaves the memory update (M0-M4) would split or free.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBEBAKE_WRITES_PROBES
#include "light_update/light_bindings.glsl"
#include "probebake/dispatch.glsl"
#include "probebake/leaf_rule.h"

layout(local_size_x = RUNTIME_WORKGROUP_SIZE) in;

void main() {
  const int listed = light_slot(probebake_flat_workgroup() * RUNTIME_WORKGROUP_SIZE + gl_LocalInvocationIndex);
  if (listed < 0 || light_slot_idle(uint(listed))) return; // as light_gather: it gathered nothing for it
  const uint slot = uint(listed);
  const uint next = uint(PROBE_SH_FLOATS) * uint(light_record_slot(slot));
  for (int v = 0; v < PROBE_SH_FLOATS; ++v) probebake_probes[slot].irradiance_sh[v] = next_irradiance[next + uint(v)];
  if (probebake_probes[slot].node < 0) return; // grid probes belong to no node
  const int verdict = leaf_verdict(probebake_probes[slot].hit_fraction, probebake_probes[slot].backface_fraction,
                                   probebake_probes[slot].depth, probebake_info, LEAF_DEAD_BACKFACE_FRACTION);
  if (verdict == LEAF_VERDICT_FREE) atomicAdd(light_counters.want_free, 1);
  else if (verdict == LEAF_VERDICT_SPLIT) atomicAdd(light_counters.want_split, 1);
}
