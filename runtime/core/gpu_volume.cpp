#include "core/gpu_volume.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>

#include "core/commands.h"
#include "core/error.h"
#include "core/volume_set.h"
#include "probebake/formats/volume_sections.h"
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

// The sections of a volume by type id (formats::for_each_section), over const or mutable memory. The leaf
// header is a section only when there are leaf entries (docs/FORMAT.md: written exactly when leaf_entries
// is); the cell index stays on the CPU.
template <class Volume>
auto sections_of(Volume& v) {
  using Byte = std::conditional_t<std::is_const_v<Volume>, const std::byte, std::byte>;
  std::array<SectionBytes<Byte>, kSectionCount> sections{};
  formats::for_each_section(v, [&](Section type, auto& member) {
    using Member = std::remove_cvref_t<decltype(member)>;
    SectionBytes<Byte>& s = sections[static_cast<std::size_t>(type)];
    if (formats::is_cell_index_section(type)) return;
    if constexpr (requires { member.data(); }) {
      s = {reinterpret_cast<Byte*>(member.data()), member.size(), sizeof(typename Member::value_type)};
    } else if constexpr (requires { member.has_value(); }) {
      s = {reinterpret_cast<Byte*>(member ? &*member : nullptr), member ? 1u : 0u, sizeof(typename Member::value_type)};
    } else {
      s = {reinterpret_cast<Byte*>(&member), 1, sizeof(Member)};
    }
  });
  if (v.leaf_entries.empty()) sections[static_cast<std::size_t>(Section::leaf_queue_header)].elements = 0;
  return sections;
}

std::string name_of(Section section) { return formats::section_name(static_cast<std::uint32_t>(section)); }

// The static tree's sections, which streaming replaces by its arena (streamed_tracing.h).
bool is_streamed_section(Section section) {
  return section == Section::trace_trees || section == Section::trace_nodes || section == Section::trace_faces ||
         section == Section::trace_vertices;
}

// The sky section rides in the lighting_info buffer after LightingInfo (volume_bindings.glsl): bytes of the
// lighting_info buffer beyond its record, at least 16 zero bytes so that sky.glsl reads a width of 0 without one.
constexpr std::size_t kSkyOffset = sizeof(gpu::LightingInfo);
std::size_t sky_tail_bytes(std::size_t sky_bytes) { return std::max<std::size_t>(sky_bytes, 16); }

} // namespace

GpuVolume::GpuVolume(Device& device, const formats::ProbeVolume& volume, std::size_t light_headroom,
                     bool streamed_tracing)
    : device_(device) {
  auto sections = sections_of(volume);
  if (streamed_tracing)
    for (std::size_t i = 0; i < kSectionCount; ++i)
      if (is_streamed_section(Section(i))) sections[i].elements = 0;
  std::size_t total = 0;
  for (std::size_t i = 0; i < kSectionCount; ++i) {
    elements_[i] = capacity_[i] = sections[i].elements;
    if (Section(i) == Section::punctual_lights) capacity_[i] += light_headroom;
    const std::size_t bytes = capacity_[i] * sections[i].element_size;
    if (bytes > device.info.max_storage_buffer_range)
      fail(StatusCode::unsupported, name_of(Section(i)) + ": " + std::to_string(bytes) +
                                        " bytes exceed maxStorageBufferRange (" +
                                        std::to_string(device.info.max_storage_buffer_range) + ") of " +
                                        device.info.name + "; bake with a coarser setting or stream cells");
    total += sections[i].bytes();
  }
  placeholder_ = device.allocator->create_buffer(16, kSectionUsage, MemoryUse::device, "placeholder");
  if (!volume.dynamic_objects.empty()) // written by ObjectPoses before anything traces
    object_instances_ = device.allocator->create_buffer(volume.dynamic_objects.size() * sizeof(gpu::ObjectInstance),
                                                        kSectionUsage, MemoryUse::device, "object instances");
  Buffer staging = device.allocator->create_buffer(std::max<std::size_t>(total, 4), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                   MemoryUse::upload, "upload staging");
  Submission submission(device);
  std::size_t offset = 0;
  const SectionBytes<const std::byte>& sky = sections[static_cast<std::size_t>(Section::sky)];
  for (std::size_t i = 0; i < kSectionCount; ++i) {
    if (Section(i) == Section::sky) continue; // in lighting_info's buffer
    const bool carries_sky = Section(i) == Section::lighting_info && sections[i].elements == 1;
    const std::size_t capacity_bytes =
        capacity_[i] * sections[i].element_size + (carries_sky ? sky_tail_bytes(sky.bytes()) : 0);
    if (capacity_bytes == 0) continue;
    buffers_[i] =
        device.allocator->create_buffer(capacity_bytes, kSectionUsage, MemoryUse::device, name_of(Section(i)));
    std::size_t bytes = sections[i].bytes();
    if (carries_sky && sky.bytes() > 0) {
      std::memcpy(static_cast<std::byte*>(staging.mapped()) + offset + kSkyOffset, sky.data, sky.bytes());
      bytes += sky.bytes();
    }
    // Headroom records stay zero (a zero intensity lights nothing) until the host fills them.
    if (capacity_bytes > bytes) vkCmdFillBuffer(submission.cmd(), buffers_[i].get(), bytes, capacity_bytes - bytes, 0);
    if (bytes == 0) continue;
    std::memcpy(static_cast<std::byte*>(staging.mapped()) + offset, sections[i].data, sections[i].bytes());
    const VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(submission.cmd(), staging.get(), buffers_[i].get(), 1, &region);
    offset += bytes;
  }
  barrier(submission.cmd(), kTransferWrite, kAnyDeviceAccess);
  submission.submit_and_wait();
  volume_set_ = make_volume_set(device, *this);
}

void GpuVolume::set_streamed_tracing(VkBuffer trees, VkBuffer arena) {
  streamed_trees_ = trees, streamed_arena_ = arena;
  write_storage_buffers(device_.vk(), volume_set_.set, volume_set_buffers(*this)); // no frame has used it yet
}

void GpuVolume::set_live_elements(Section section, std::size_t count) {
  const auto i = static_cast<std::size_t>(section);
  if (count > capacity_[i])
    fail(StatusCode::internal, name_of(section) + ": " + std::to_string(count) + " live elements exceed the capacity " +
                                   std::to_string(capacity_[i]));
  elements_[i] = count;
}

VkBuffer GpuVolume::binding(Section section) const {
  if (streamed_arena_ != VK_NULL_HANDLE && is_streamed_section(section))
    return section == Section::trace_trees ? streamed_trees_ : streamed_arena_;
  const Buffer& b = buffer(section);
  return b ? b.get() : placeholder_.get();
}

formats::ProbeVolume GpuVolume::read_back(const formats::ProbeVolume& cpu_parts) const {
  formats::ProbeVolume out;
  out.cell_depth = cpu_parts.cell_depth;
  out.cells = cpu_parts.cells;
  out.cell_tracing = cpu_parts.cell_tracing;
  out.input_hash = cpu_parts.input_hash;
  formats::for_each_section(out, [&](Section type, auto& member) {
    if constexpr (requires { member.resize(0); }) {
      if (!formats::is_cell_index_section(type)) member.resize(elements(type));
    } else if constexpr (requires { member.emplace(); }) {
      if (elements(type) != 0) member.emplace();
    }
  });
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
    const bool sky = Section(i) == Section::sky;
    const VkBufferCopy region{sky ? kSkyOffset : 0, offset, sections[i].bytes()};
    vkCmdCopyBuffer(submission.cmd(), sky ? buffer(Section::lighting_info).get() : buffers_[i].get(), staging.get(), 1,
                    &region);
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
