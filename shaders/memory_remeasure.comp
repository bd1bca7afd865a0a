// Memory update, streaming (one thread per octree element, in frames where cells arrived, after collapse):
// the leaves and parents whose last measure crossed a cell that is out (MEMORY_MARK_REMEASURE) are queued
// again, leaves with a probe for L1, probe-less leaves for M1 (as the box that touched them asked; L1 then
// measures the new probe) and parents for M4, so that the measures that could not decide are made again
// with the geometry that arrived. Those still unresolved are marked again.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probebake/memory_bindings.glsl"
#include "probebake/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void main() {
  const int node = memory_item(probebake_info.octree_elements);
  if (node < 0 || node_marks[node] != MEMORY_MARK_REMEASURE) return;
  node_marks[node] = 0;
  if (!octree_is_live_node(node)) return; // its cluster was freed since
  const int v = probebake_octree[node];
  if (v < 0) {
    queue_push(memory_light_out(), node, LEAF_L1_PLACE_SURFELS);
  } else if (v == 0) {
    queue_push(memory_memory_out(), node, LEAF_M1_ALLOCATE_PROBE);
    queue_push_parent(memory_memory_out(), node, LEAF_M0_CHILD_ALLOCATING);
  } else {
    queue_push(memory_memory_out(), node, LEAF_M4_FREE_CLUSTER);
  }
}
