// Memory update, streaming (one thread per octree element, in frames where cells arrived, after collapse):
// the leaves and parents whose last measure crossed a cell that is out (MEMORY_MARK_REMEASURE) are queued
// again, leaves with a probe for L1, probe-less leaves for M1 (as the box that touched them asked; L1 then
// measures the new probe) and parents for M4, so that the measures that could not decide are made again
// with the geometry that arrived. Those still unresolved are marked again.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void main() {
  const int node = memory_item(probebake_info.octree_elements);
  if (node < 0 || node_marks[node] != MEMORY_MARK_REMEASURE) return;
  node_marks[node] = 0;
  if (octree_is_live_node(node)) queue_measure_again(node); // else its cluster was freed since
}
