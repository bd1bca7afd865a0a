// End of the frame's queue work (one thread per entry slot of all three segments): writes every entry's
// state from its key, so that the stored leaf buffer is the thesis's (node, state) pairs that LeafQueue and
// the validator read. (A segment never overflows: the host gives it capacity >= octree elements.)
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

void main() {
  const int slot = memory_item(3 * queue_capacity());
  if (slot < 0) return;
  if (slot == 0) {
    memory_counters.free_clusters = memory_state.cluster_top;
    memory_counters.free_probes = memory_state.probe_top;
    memory_counters.free_batches = memory_state.batch_top;
  }
  const int segment = slot / queue_capacity(), index = slot % queue_capacity();
  if (index >= leaf_header.count[segment]) return;
  const int node = leaf_entries[slot].node;
  if (node >= 0 && node < queue_capacity()) leaf_entries[slot].state = queue_keys[queue_key_index(segment, node)] & MEMORY_KEY_STATE_MASK;
}
