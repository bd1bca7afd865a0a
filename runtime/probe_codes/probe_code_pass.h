// The compact probes a game looks up (UploadOptions::probe_code, formats/sh_codec.h): a point (position,
// allocated or free) and an l1 or l2 code per probe slot, encoded on the GPU from the probe records after
// every frame's light update (and once at upload), so that the lookups read 32 or 48 bytes per probe
// instead of the 144-byte record the light update keeps in floats.
#pragma once

#include <cstdint>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/commands.h"
#include "core/device.h"
#include "core/gpu_volume.h"
#include "core/pipelines.h"
#include "probebake/formats/sh_codec.h"

namespace probebake::runtime::detail {

class ProbeCodePass {
public:
  // `codec` is l1 or l2.
  ProbeCodePass(Device& device, const GpuVolume& volume, formats::ShCodec codec);

  // Records the encode of every slot between timer slot `timer_slot`'s timestamps (no timer: untimed).
  void record(VkCommandBuffer cmd, PassTimer* timer = nullptr, std::uint32_t timer_slot = 0) const;

  std::uint32_t code_bands() const { return code_bands_; } // 1 (l1) or 2 (l2)
  const Buffer& points() const { return points_; }
  const Buffer& codes() const { return codes_; }

private:
  Device& device_;
  const GpuVolume& volume_;
  std::uint32_t probe_capacity_ = 0;
  std::uint32_t code_bands_ = 0;
  Buffer points_, codes_;
  PassDescriptorSet descriptors_;
};

} // namespace probebake::runtime::detail
