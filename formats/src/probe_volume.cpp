// ProbeVolume helpers: an empty volume and keeping VolumeInfo's counts equal to the buffer sizes.
#include "probebake/formats/probe_volume.h"

#include <limits>
#include <string>

#include "probebake/formats/error.h"
#include "probebake/formats/trace_mesh.h"

namespace probebake::formats {
namespace {

int checked_count(std::size_t size, const char* what) {
  if (size > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(ErrorKind::internal, std::string(what) + ": more than INT32_MAX elements");
  }
  return static_cast<int>(size);
}

} // namespace

ProbeVolume make_empty_volume(const gpu::VolumeInfo& settings) {
  ProbeVolume volume;
  volume.info = settings;
  volume.octree.assign(1, 0); // the root: a leaf without probe
  volume.probe_index.assign(1, gpu::PROBE_INDEX_END);
  sync_info_counts(volume);
  return volume;
}

void sync_info_counts(ProbeVolume& volume) {
  volume.info.octree_elements = checked_count(volume.octree.size(), "octree");
  volume.info.probe_capacity = checked_count(volume.probes.size(), "probes");
  volume.info.batch_capacity = checked_count(volume.surfel_batches.size(), "surfel_batches");
  volume.info.svo_nodes = checked_count(volume.svo_nodes.size(), "svo_nodes");
  volume.info.svo_leaves = checked_count(volume.svo_leaves.size(), "svo_leaves");
  if (!volume.lighting) return;
  gpu::LightingInfo& lighting = *volume.lighting;
  const bool float_layout = has_float_tracing(volume); // a 1.1-1.3 file
  lighting.bvh_nodes = checked_count(float_layout ? volume.bvh_nodes.size() : volume.trace_nodes.size(), "bvh_nodes");
  lighting.triangles =
      checked_count(float_layout ? volume.trace_triangles.size() : volume.trace_faces.size(), "trace_triangles");
  lighting.lights = checked_count(volume.punctual_lights.size(), "punctual_lights");
  lighting.emitter_patches = checked_count(volume.emitter_patches.size(), "emitter_patches");
  lighting.dynamic_objects = checked_count(volume.dynamic_objects.size(), "dynamic_objects");
}

void init_leaf_queue(ProbeVolume& volume, int segment_capacity) {
  if (segment_capacity < 0 || segment_capacity > std::numeric_limits<std::int32_t>::max() / 3) {
    throw Error(ErrorKind::internal, "leaf queue: bad segment capacity " + std::to_string(segment_capacity));
  }
  volume.leaf_header = gpu::LeafQueueHeader{};
  volume.leaf_header.segment_capacity = segment_capacity;
  volume.leaf_entries.assign(static_cast<std::size_t>(segment_capacity) * 3, gpu::LeafEntry{});
}

} // namespace probebake::formats
