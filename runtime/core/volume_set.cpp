#include "core/volume_set.h"

#include "core/device.h"
#include "core/gpu_volume.h"

namespace probebake::runtime::detail {
namespace {

struct VolumeBinding {
  std::uint32_t binding;
  Section section;
};

// Binding -> section; VOLUME_BINDING_OBJECT_INSTANCES is the runtime's own (GpuVolume::object_instances).
constexpr VolumeBinding kVolumeBindings[] = {
    {gpu::VOLUME_BINDING_VOLUME_INFO, Section::volume_info},
    {gpu::VOLUME_BINDING_PROBES, Section::probes},
    {gpu::VOLUME_BINDING_SVO_NODES, Section::svo_nodes},
    {gpu::VOLUME_BINDING_SVO_LEAVES, Section::svo_leaves},
    {gpu::VOLUME_BINDING_OCTREE, Section::octree},
    {gpu::VOLUME_BINDING_PROBE_INDEX, Section::probe_index},
    {gpu::VOLUME_BINDING_SURFEL_BATCHES, Section::surfel_batches},
    {gpu::VOLUME_BINDING_LEAF_HEADER, Section::leaf_queue_header},
    {gpu::VOLUME_BINDING_LEAF_ENTRIES, Section::leaf_entries},
    {gpu::VOLUME_BINDING_LIGHTING_INFO, Section::lighting_info},
    {gpu::VOLUME_BINDING_RAY_DIRECTIONS, Section::ray_directions},
    {gpu::VOLUME_BINDING_PUNCTUAL_LIGHTS, Section::punctual_lights},
    {gpu::VOLUME_BINDING_EMITTER_PATCHES, Section::emitter_patches},
    {gpu::VOLUME_BINDING_TRACE_TREES, Section::trace_trees},
    {gpu::VOLUME_BINDING_TRACE_NODES, Section::trace_nodes},
    {gpu::VOLUME_BINDING_TRACE_FACES, Section::trace_faces},
    {gpu::VOLUME_BINDING_TRACE_VERTICES, Section::trace_vertices},
    {gpu::VOLUME_BINDING_TRACE_MATERIALS, Section::trace_materials},
    {gpu::VOLUME_BINDING_DYNAMIC_OBJECTS, Section::dynamic_objects},
};
static_assert(std::size(kVolumeBindings) + 1 == gpu::VOLUME_BINDING_COUNT, "a volume binding without a section");

} // namespace

std::array<VkBuffer, gpu::VOLUME_BINDING_COUNT> volume_set_buffers(const GpuVolume& volume) {
  std::array<VkBuffer, gpu::VOLUME_BINDING_COUNT> buffers{};
  for (const VolumeBinding& b : kVolumeBindings) buffers[b.binding] = volume.binding(b.section);
  buffers[gpu::VOLUME_BINDING_OBJECT_INSTANCES] = volume.object_instances();
  return buffers;
}

PassDescriptorSet make_volume_set(Device& device, const GpuVolume& volume) {
  return make_pass_descriptor_set(device.vk(), device.compute_pipelines().volume_set_layout(),
                                  volume_set_buffers(volume));
}

} // namespace probebake::runtime::detail
