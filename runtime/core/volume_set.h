// The volume set: descriptor set 0 of every runtime kernel, one storage buffer per file section a kernel
// reads (VOLUME_BINDING_* of probebake/bindings.h) plus the dynamic objects' poses. GpuVolume owns it and
// writes it again when streaming hands the tracing sections to its arena.
#pragma once

#include <array>

#include <vulkan/vulkan_core.h>

#include "core/pipelines.h"
#include "probebake/bindings.h"

namespace probebake::runtime::detail {

class GpuVolume;
struct Device;

// The buffer of each binding of the volume set, in binding order.
std::array<VkBuffer, gpu::VOLUME_BINDING_COUNT> volume_set_buffers(const GpuVolume& volume);

PassDescriptorSet make_volume_set(Device& device, const GpuVolume& volume);

} // namespace probebake::runtime::detail
