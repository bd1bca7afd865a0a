#include "gpu_volume.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>

#include "commands.h"
#include "error.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

constexpr VkBufferUsageFlags kSectionUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

template <class Byte>
struct SectionBytes {
  Byte* data = nullptr;
  std::size_t elements = 0;
  std::size_t element_size = 0;
  std::size_t bytes() const { return elements * element_size; }
};

template <class Byte, class T>
SectionBytes<Byte> one(T& value) {
  return {reinterpret_cast<Byte*>(&value), 1, sizeof(T)};
}

// A singleton section that a volume may lack (std::optional, const or not).
template <class Byte, class Optional>
SectionBytes<Byte> optional_one(Optional& value) {
  return {reinterpret_cast<Byte*>(value ? &*value : nullptr), value ? 1u : 0u,
          sizeof(typename std::decay_t<Optional>::value_type)};
}

template <class Byte, class Vector>
SectionBytes<Byte> many(Vector& vector) {
  return {reinterpret_cast<Byte*>(vector.data()), vector.size(), sizeof(typename std::decay_t<Vector>::value_type)};
}

// The sections of a volume in Section order, over const or mutable memory. The leaf header is a section
// only when there are leaf entries (docs/FORMAT.md: written exactly when leaf_entries is).
template <class Volume>
auto sections_of(Volume& v) {
  using Byte = std::conditional_t<std::is_const_v<Volume>, const std::byte, std::byte>;
  SectionBytes<Byte> header = one<Byte>(v.leaf_header);
  if (v.leaf_entries.empty()) header.elements = 0;
  return std::array<SectionBytes<Byte>, kSectionCount>{
      one<Byte>(v.info),        many<Byte>(v.octree),      many<Byte>(v.probes),
      many<Byte>(v.surfel_batches), header,                many<Byte>(v.leaf_entries),
      many<Byte>(v.probe_index), many<Byte>(v.svo_nodes), many<Byte>(v.svo_leaves),
      optional_one<Byte>(v.lighting), many<Byte>(v.ray_directions), many<Byte>(v.bvh_nodes),
      many<Byte>(v.trace_triangles), many<Byte>(v.punctual_lights), many<Byte>(v.emitter_patches),
      many<Byte>(v.dynamic_objects)};
}

} // namespace

const char* section_name(Section section) {
  static constexpr const char* kNames[kSectionCount] = {
      "volume_info", "octree", "probes", "surfel_batches", "leaf_queue_header",
      "leaf_entries", "probe_index", "svo_nodes", "svo_leaves", "lighting_info",
      "ray_directions", "bvh_nodes", "trace_triangles", "punctual_lights", "emitter_patches",
      "dynamic_objects"};
  return kNames[static_cast<std::size_t>(section)];
}

GpuVolume::GpuVolume(Device& device, const formats::ProbeVolume& volume, std::size_t light_headroom) : device_(device) {
  const auto sections = sections_of(volume);
  std::size_t total = 0;
  for (std::size_t i = 0; i < kSectionCount; ++i) {
    elements_[i] = capacity_[i] = sections[i].elements;
    if (Section(i) == Section::punctual_lights) capacity_[i] += light_headroom;
    const std::size_t bytes = capacity_[i] * sections[i].element_size;
    if (bytes > device.info.max_storage_buffer_range)
      fail(StatusCode::unsupported, std::string(section_name(Section(i))) + ": " + std::to_string(bytes) +
                                        " bytes exceed maxStorageBufferRange (" +
                                        std::to_string(device.info.max_storage_buffer_range) + ") of " +
                                        device.info.name + "; bake with a coarser setting or stream cells");
    total += sections[i].bytes();
  }
  placeholder_ = device.allocator->create_buffer(16, kSectionUsage, MemoryUse::device, "placeholder");
  if (!volume.dynamic_objects.empty()) // written by ObjectPoses before anything traces
    object_instances_ = device.allocator->create_buffer(volume.dynamic_objects.size() * sizeof(gpu::ObjectInstance), kSectionUsage,
                                                        MemoryUse::device, "object instances");
  Buffer staging = device.allocator->create_buffer(std::max<std::size_t>(total, 4), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                   MemoryUse::upload, "upload staging");
  Submission submission(device);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < kSectionCount; ++i) {
    const std::size_t capacity_bytes = capacity_[i] * sections[i].element_size;
    if (capacity_bytes == 0) continue;
    buffers_[i] = device.allocator->create_buffer(capacity_bytes, kSectionUsage, MemoryUse::device, section_name(Section(i)));
    const std::size_t bytes = sections[i].bytes();
    // Headroom records stay zero (a zero intensity lights nothing) until the host fills them.
    if (capacity_bytes > bytes) vkCmdFillBuffer(submission.cmd(), buffers_[i].get(), bytes, capacity_bytes - bytes, 0);
    if (bytes == 0) continue;
    std::memcpy(static_cast<std::byte*>(staging.mapped()) + offset, sections[i].data, bytes);
    const VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(submission.cmd(), staging.get(), buffers_[i].get(), 1, &region);
    offset += bytes;
  }
  barrier(submission.cmd(), kTransferWrite, kAnyDeviceAccess);
  submission.submit_and_wait();
}

void GpuVolume::set_live_elements(Section section, std::size_t count) {
  const auto i = static_cast<std::size_t>(section);
  if (count > capacity_[i])
    fail(StatusCode::internal, std::string(section_name(section)) + ": " + std::to_string(count) +
                                   " live elements exceed the capacity " + std::to_string(capacity_[i]));
  elements_[i] = count;
}

VkBuffer GpuVolume::binding(Section section) const {
  const Buffer& b = buffer(section);
  return b ? b.get() : placeholder_.get();
}

formats::ProbeVolume GpuVolume::read_back(const formats::ProbeVolume& cpu_parts) const {
  formats::ProbeVolume out;
  out.cell_depth = cpu_parts.cell_depth;
  out.cells = cpu_parts.cells;
  out.input_hash = cpu_parts.input_hash;
  out.octree.resize(elements(Section::octree));
  out.probes.resize(elements(Section::probes));
  out.surfel_batches.resize(elements(Section::surfel_batches));
  out.leaf_entries.resize(elements(Section::leaf_entries));
  out.probe_index.resize(elements(Section::probe_index));
  out.svo_nodes.resize(elements(Section::svo_nodes));
  out.svo_leaves.resize(elements(Section::svo_leaves));
  if (elements(Section::lighting_info) != 0) out.lighting.emplace();
  out.ray_directions.resize(elements(Section::ray_directions));
  out.bvh_nodes.resize(elements(Section::bvh_nodes));
  out.trace_triangles.resize(elements(Section::trace_triangles));
  out.punctual_lights.resize(elements(Section::punctual_lights));
  out.emitter_patches.resize(elements(Section::emitter_patches));
  out.dynamic_objects.resize(elements(Section::dynamic_objects));
  const auto sections = sections_of(out);

  std::size_t total = 0;
  for (const auto& s : sections) total += s.bytes();
  Buffer staging = device_.allocator->create_buffer(total, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::readback,
                                                    "read-back staging");
  Submission submission(device_);
  barrier(submission.cmd(), kAnyDeviceAccess, kTransferRead);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < kSectionCount; ++i) {
    if (sections[i].bytes() == 0) continue;
    const VkBufferCopy region{0, offset, sections[i].bytes()};
    vkCmdCopyBuffer(submission.cmd(), buffers_[i].get(), staging.get(), 1, &region);
    offset += sections[i].bytes();
  }
  barrier(submission.cmd(), kTransferWrite, kHostRead);
  submission.submit_and_wait();
  offset = 0;
  for (const auto& s : sections) {
    if (s.bytes() == 0) continue;
    std::memcpy(s.data, static_cast<const std::byte*>(staging.mapped()) + offset, s.bytes());
    offset += s.bytes();
  }
  return out;
}

} // namespace probebake::runtime::detail
