// The storage buffers of one probe volume: one per .probes section, each byte-for-byte the section
// (gpu_types.h, std430), created only for the sections the volume uses. Upload through one staging
// buffer; read-back of every buffer into a ProbeVolume.
#pragma once

#include <array>
#include <cstddef>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/device.h"
#include "core/pipelines.h"
#include "probebake/formats/container.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::runtime::detail {

// The file's sections (formats/volume_sections.h, the one list), indexed by their type id; cells are
// CPU-side data and get no buffer.
using Section = formats::SectionType;
inline constexpr std::size_t kSectionCount = formats::kSectionTypeCount + 1; // ids start at 1

class GpuVolume {
public:
  // Creates the buffers and uploads `volume`; the punctual_lights buffer gets room for `light_headroom`
  // more records (zeroed). Throws RuntimeError(unsupported) when a section is larger than
  // maxStorageBufferRange, naming the section and both sizes.
  // `streamed_tracing`: the static tree's sections (trees, nodes, faces, vertices) get no buffer here; the
  // streaming arena (streamed_tracing.h) takes their bindings through set_streamed_tracing().
  GpuVolume(Device& device, const formats::ProbeVolume& volume, std::size_t light_headroom = 0,
            bool streamed_tracing = false);

  // A copy of every buffer; the CPU-only members (cells, cell_depth, input_hash) come from `cpu_parts`.
  formats::ProbeVolume read_back(const formats::ProbeVolume& cpu_parts) const;

  // The section's buffer, or an empty Buffer when the volume has no such section.
  const Buffer& buffer(Section section) const { return buffers_[static_cast<std::size_t>(section)]; }
  // The section's buffer for descriptor sets: a 16-byte placeholder when the section is empty (shaders
  // check the counts in VolumeInfo and never read it); the streaming arena for the streamed sections.
  VkBuffer binding(Section section) const;
  // Streaming: trace_trees binds `trees`, and trace_nodes, trace_faces and trace_vertices all bind `arena`
  // (each its own array over the same bytes). Call before any pass binds the tracing sections.
  // The volume set is written again with them.
  void set_streamed_tracing(VkBuffer trees, VkBuffer arena);
  // Descriptor set 0 of every kernel (volume_set.h): the sections' bindings.
  VkDescriptorSet volume_set() const { return volume_set_.set; }
  // Live elements of the section: its vector's size at upload, or what set_live_elements() last said.
  std::size_t elements(Section section) const { return elements_[static_cast<std::size_t>(section)]; }
  // Elements the section's buffer holds (elements() at upload, plus the light headroom).
  std::size_t capacity(Section section) const { return capacity_[static_cast<std::size_t>(section)]; }
  // A pass changed the live count (host light updates); read_back() copies that many. Precondition:
  // count <= capacity(section).
  void set_live_elements(Section section, std::size_t count);
  // The runtime's ObjectInstance per dynamic object (runtime_types.h; ObjectPoses writes it), or the
  // placeholder for a volume without dynamic objects.
  VkBuffer object_instances() const { return object_instances_ ? object_instances_.get() : placeholder_.get(); }

private:
  Device& device_;
  std::array<Buffer, kSectionCount> buffers_;
  std::array<std::size_t, kSectionCount> elements_{};
  std::array<std::size_t, kSectionCount> capacity_{};
  Buffer placeholder_;
  Buffer object_instances_;
  VkBuffer streamed_trees_ = VK_NULL_HANDLE, streamed_arena_ = VK_NULL_HANDLE;
  PassDescriptorSet volume_set_;
};

} // namespace probebake::runtime::detail
