// SVO refresh after the memory update (one thread per SVO leaf): a stencil slot whose probe was freed or
// reused since the slot was filled (probe generation changed) is dropped and the remaining weights are
// renormalised (only in leaves that lost a slot), so that no lookup reads a freed or moved probe; a leaf left
// empty is refilled from the octree leaves around its voxel centre, or detached (a miss) until it can be.
// The SVO's shape is the bake's, less the detached voxels.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "memory_update/memory_bindings.glsl"
#include "memory_update/memory_update.glsl"

layout(local_size_x = MEMORY_WORKGROUP_SIZE) in;

// The probe of the octree leaf containing `p`, or -1.
int octree_probe_at(vec3 p) {
  precise vec3 cube_min = probebake_info.root_min;
  precise float size = probebake_info.root_size;
  int node = 0;
  for (int depth = 0; depth <= OCTREE_MAX_DEPTH; ++depth) {
    const int v = probebake_octree[node];
    if (v <= 0) return v < 0 ? ~v : -1;
    size = 0.5 * size;
    const vec3 mid = cube_min + vec3(size);
    const ivec3 upper = ivec3(greaterThanEqual(p, mid));
    cube_min = cube_min + vec3(upper) * size;
    node = v + 1 + (upper.x | (upper.y << 1) | (upper.z << 2));
  }
  return -1;
}

// Fills SVO leaf `leaf` (voxel centre c, SVO node `node`) from the octree: the distinct probes of the octree
// leaves at c and at eight points towards the voxel's corners, equal weights; with none, the voxel is
// detached (SVO node 0: a miss) and retried every frame.
void refill(int leaf, int node, vec3 c) {
  ivec4 probes = ivec4(-1);
  uvec4 generations = uvec4(0u);
  int used = 0;
  const float reach = 0.45 * probebake_info.root_size / float(1 << clamp(probebake_info.svo_depth, 0, 30));
  for (int k = 0; k < 9 && used < SVO_PROBES_PER_LEAF; ++k) {
    const vec3 corner = k == 0 ? vec3(0.0) : vec3(float((k - 1) & 1), float(((k - 1) >> 1) & 1), float(((k - 1) >> 2) & 1)) * 2.0 - 1.0;
    const int probe = octree_probe_at(c + reach * corner);
    if (probe < 0 || probe == probes.x || probe == probes.y || probe == probes.z) continue;
    probes[used] = probe;
    generations[used] = probe_generations[probe];
    ++used;
  }
  probebake_svo_leaves[leaf].probes = probes;
  probebake_svo_leaves[leaf].weights = used > 0 ? vec4(lessThan(ivec4(0, 1, 2, 3), ivec4(used))) / float(used) : vec4(0.0);
  svo_generations[leaf] = generations;
  probebake_svo_nodes[node] = used > 0 ? ~leaf : 0;
  if (used > 0) atomicAdd(memory_counters.svo_leaves_refilled, 1);
}

void main() {
  const int leaf = memory_item(probebake_info.svo_leaves);
  if (leaf < 0) return;
  const vec3 centre = intBitsToFloat(svo_bake[leaf].xyz);
  const int node = int(intBitsToFloat(svo_bake[leaf].w));
  if (probebake_svo_nodes[node] != ~leaf) { refill(leaf, node, centre); return; } // detached earlier
  ivec4 probes = ivec4(-1);
  vec4 weights = vec4(0.0);
  uvec4 generations = uvec4(0u);
  int used = 0;
  int dropped = 0;
  float sum = 0.0;
  for (int k = 0; k < SVO_PROBES_PER_LEAF; ++k) {
    if (probebake_svo_leaves[leaf].probes[k] < 0) continue;
    if (!svo_slot_live(leaf, k)) { ++dropped; continue; }
    probes[used] = probebake_svo_leaves[leaf].probes[k];
    weights[used] = probebake_svo_leaves[leaf].weights[k];
    generations[used] = svo_generations[leaf][k];
    sum += weights[used];
    ++used;
  }
  if (dropped == 0) return; // untouched: the stored weights stay bit for bit
  atomicAdd(memory_counters.svo_slots_dropped, dropped);
  if (used == 0 || !(sum > 0.0)) { refill(leaf, node, centre); return; }
  probebake_svo_leaves[leaf].probes = probes;
  probebake_svo_leaves[leaf].weights = weights / sum;
  svo_generations[leaf] = generations;
}
