// The irradiance sampling pass: queries (position, normal) in, SampleResult out, through
// sample_irradiance.comp (or sample_grid.comp), which runs the GLSL include games use
// (probebake/sample_irradiance.glsl, probebake/sample_grid.glsl).
// Batches are split so that no query or result buffer exceeds maxStorageBufferRange.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan_core.h>

#include "core/device.h"
#include "core/gpu_volume.h"
#include "core/handles.h"

namespace probebake::runtime::detail {

class SamplePass {
public:
  SamplePass(Device& device, const GpuVolume& volume);

  // out[i] = irradiance at (positions[i], normals[i]); sizes must be equal (checked by the caller).
  // SampleMethod::all_probes throws RuntimeError(unsupported) for volumes without the lighting sections,
  // SampleMethod::grid for volumes without a grid lattice.
  // `flags` (optional, out.size() entries): each lookup's kSample* bits.
  void run(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals, std::span<glm::vec3> out,
           SampleStats& stats, SampleMethod method, std::span<std::uint32_t> flags = {});
  // Streaming: the light update's record slots, so that results say when their probes are not lit.
  void set_record_slots(VkBuffer record_slots) { record_slots_ = record_slots; }
  // Compact probes (probe_codes/): the SVO and grid samplers read these points and codes (`bands` blocks per
  // probe) instead of the probe records, as a game's shader does; the all-probe baseline keeps the records.
  void set_probe_codes(VkBuffer points, VkBuffer codes, std::uint32_t bands) {
    points_ = points;
    codes_ = codes;
    code_bands_ = bands;
  }

  // Queries per dispatch: limited by maxStorageBufferRange and by a staging budget.
  std::size_t max_batch() const { return max_batch_; }

private:
  Device& device_;
  const GpuVolume& volume_;
  std::size_t max_batch_ = 0;
  DeviceObject<VkDescriptorPool> pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;                      // SVO sampler
  VkDescriptorSet grid_set_ = VK_NULL_HANDLE;                 // grid engine
  VkDescriptorSet all_set_ = VK_NULL_HANDLE;                  // all-probe baseline
  VkBuffer record_slots_ = VK_NULL_HANDLE;                    // streaming only
  VkBuffer points_ = VK_NULL_HANDLE, codes_ = VK_NULL_HANDLE; // compact probes only
  std::uint32_t code_bands_ = 0;
};

} // namespace probebake::runtime::detail
