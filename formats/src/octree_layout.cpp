// Read-only octree queries on the buffer layout of the octree thesis §3.1.1 (cubes, walks, point
// location) and the probe index list of §3.1.5. All of them are safe on malformed buffers: a broken
// link throws Error(input) instead of reading out of range or looping.
#include <array>
#include <cmath>
#include <string>

#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"

namespace probebake::formats {
namespace {

[[noreturn]] void throw_broken(const std::string& what) {
  throw Error(ErrorKind::input, "octree: " + what + " (run probebake validate)");
}

// Meta index of the child cluster of parent node value `value`, checked to be a complete cluster.
int checked_child_meta(const std::vector<std::int32_t>& octree, int node) {
  const int value = octree[node];
  if (!is_meta_index(value) || static_cast<std::size_t>(value) + 9 > octree.size()) {
    throw_broken("node " + std::to_string(node) + " has child index " + std::to_string(value) +
                 " that is not a complete cluster");
  }
  return value;
}

glm::vec3 octant_offset(int octant) {
  return glm::vec3(static_cast<float>(octant & 1), static_cast<float>((octant >> 1) & 1),
                   static_cast<float>((octant >> 2) & 1));
}

} // namespace

NodeCube root_cube(const gpu::VolumeInfo& info) { return NodeCube{0, 0, info.root_min, info.root_size}; }

NodeCube child_cube(const NodeCube& parent, int octant) {
  const float half = 0.5f * parent.size;
  return NodeCube{0, parent.depth + 1, parent.min + octant_offset(octant) * half, half};
}

NodeCube node_cube(const ProbeVolume& volume, int node) {
  const std::vector<std::int32_t>& octree = volume.octree;
  if (node < 0 || static_cast<std::size_t>(node) >= octree.size() || !is_node_index(node)) {
    throw_broken("node " + std::to_string(node) + " is not a node index");
  }
  std::array<int, gpu::OCTREE_MAX_DEPTH> octants{};
  int depth = 0;
  for (int current = node; current != gpu::OCTREE_ROOT;) {
    const int meta = cluster_meta_of(current);
    const int parent = ~octree[meta];
    if (depth == gpu::OCTREE_MAX_DEPTH || octree[meta] >= 0 || parent < 0 ||
        static_cast<std::size_t>(parent) >= octree.size() || octree[parent] != meta) {
      throw_broken("node " + std::to_string(current) + " has no valid parent link");
    }
    octants[depth++] = octant_of(current);
    current = parent;
  }
  NodeCube cube = root_cube(volume.info);
  for (int level = depth - 1; level >= 0; --level) cube = child_cube(cube, octants[level]);
  cube.node = node;
  return cube;
}

void for_each_leaf(const ProbeVolume& volume, const std::function<void(const NodeCube&)>& visit) {
  const std::vector<std::int32_t>& octree = volume.octree;
  if (octree.empty()) throw_broken("no root node");
  std::vector<bool> cluster_seen(complete_clusters(octree.size()), false);
  std::vector<NodeCube> stack{root_cube(volume.info)};
  while (!stack.empty()) {
    const NodeCube cube = stack.back();
    stack.pop_back();
    if (octree[cube.node] <= 0) {
      visit(cube);
      continue;
    }
    const int meta = checked_child_meta(octree, cube.node);
    const std::size_t cluster = static_cast<std::size_t>(meta - 1) / 9;
    if (cluster_seen[cluster]) throw_broken("cluster " + std::to_string(meta) + " is reached twice");
    if (cube.depth >= gpu::OCTREE_MAX_DEPTH) throw_broken("deeper than OCTREE_MAX_DEPTH");
    cluster_seen[cluster] = true;
    for (int octant = 7; octant >= 0; --octant) { // reversed: octant 0 is visited first
      NodeCube child = child_cube(cube, octant);
      child.node = child_node(meta, octant);
      stack.push_back(child);
    }
  }
}

std::optional<NodeCube> find_leaf(const ProbeVolume& volume, glm::vec3 point) {
  if (volume.octree.empty()) throw_broken("no root node");
  NodeCube cube = root_cube(volume.info);
  for (int axis = 0; axis < 3; ++axis) {
    // Written so that NaN fails the test.
    if (!(point[axis] >= cube.min[axis] && point[axis] <= cube.min[axis] + cube.size)) return std::nullopt;
  }
  while (volume.octree[cube.node] > 0) {
    if (cube.depth >= gpu::OCTREE_MAX_DEPTH) throw_broken("deeper than OCTREE_MAX_DEPTH");
    const int meta = checked_child_meta(volume.octree, cube.node);
    const glm::vec3 centre = cube.centre();
    const int octant = (point.x >= centre.x ? 1 : 0) | (point.y >= centre.y ? 2 : 0) | (point.z >= centre.z ? 4 : 0);
    cube = child_cube(cube, octant);
    cube.node = child_node(meta, octant);
  }
  return cube;
}

void rebuild_probe_index(ProbeVolume& volume) {
  volume.probe_index.assign(volume.probes.size() + 1, gpu::PROBE_INDEX_END);
  std::size_t used = 0;
  for (std::size_t probe = 0; probe < volume.probes.size(); ++probe) {
    if (volume.probes[probe].link != 0) volume.probe_index[used++] = static_cast<std::int32_t>(probe);
  }
}

} // namespace probebake::formats
