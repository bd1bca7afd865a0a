// The host's punctual lights (FrameInputs::lights): checked against the light buffer's capacity and the
// record's ranges, then recorded into the frame as one upload of the records that changed (vkCmdUpdateBuffer
// into the punctual_lights section, in 64 KiB pieces) and, when the count changed, of lighting_info.lights.
// Nothing is allocated per frame: the buffer was sized at upload (file count + UploadOptions::light_headroom).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "core/gpu_volume.h"
#include "probebake/runtime_types.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

// vkCmdUpdateBuffer in pieces of at most 65536 bytes (its limit per call); bytes and offset multiples of 4.
void update_buffer(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset, const void* data, std::size_t bytes);

// Every component finite and >= 0 (the host's radiances and scales: FrameInputs::sky, FrameInputs::emitters).
bool finite_non_negative(const glm::vec3& v);

// ok, or invalid_argument naming the first bad light and field, or the count against `capacity`.
Status check_lights(std::span<const gpu::PunctualLight> lights, std::size_t capacity);

class LightInputs {
public:
  // The file's lights (the volume's live punctual_lights) and the buffer's capacity.
  LightInputs(std::span<const gpu::PunctualLight> file_lights, std::size_t capacity);

  // Records the upload of what differs between `lights` (checked by check_lights; the fields a light's type
  // does not use are written as zero, as the bake writes them) and the current lights,
  // followed by a barrier to the compute passes that read them; updates `volume`'s live count. Returns the
  // records uploaded. Records nothing when nothing changed.
  int record(VkCommandBuffer cmd, GpuVolume& volume, std::span<const gpu::PunctualLight> lights);

  // What the last record() changed: per changed light its record before and after (an added or removed light
  // is a zero-intensity record on the other side). Empty when nothing changed.
  std::span<const gpu::LightChange> changes() const { return changes_; }
  // The light index of changes()[0].
  std::size_t first_change() const { return first_change_; }
  std::span<const gpu::PunctualLight> current() const { return current_; }
  std::size_t capacity() const { return capacity_; }

private:
  std::vector<gpu::PunctualLight> current_; // both reserved to the capacity at construction
  std::vector<gpu::PunctualLight> staged_;  // this frame's records with unused fields zeroed
  std::vector<gpu::LightChange> changes_;   // reserved to the capacity
  std::size_t first_change_ = 0;
  std::size_t capacity_ = 0;
};

} // namespace probebake::runtime::detail
