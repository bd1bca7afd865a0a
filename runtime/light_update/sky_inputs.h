// The host's sky (FrameInputs::sky): checked against the file's sky, then recorded into the frame as an upload of
// LightingInfo::sky_radiance and the map's texels (the sky section) when they differ from the current ones, after
// which light_sky relights the records of rays that left the scene. Nothing is allocated per frame.
#pragma once

#include <optional>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan_core.h>

#include "core/gpu_volume.h"
#include "probebake/runtime/vocabulary.h"
#include "probebake/sky_map.h"

namespace probebake::runtime::detail {

class SkyInputs {
public:
  // The file's sky: its lighting_info's sky_radiance and its sky section (empty: none).
  SkyInputs(glm::vec3 radiance, std::span<const std::uint32_t> sky_section);

  // ok, or invalid_argument naming the first bad value, or a map whose size is not the file's.
  Status check(const SkyInput& sky) const;
  // Records the upload of what differs (checked by check()), between barriers; returns whether anything did.
  bool record(VkCommandBuffer cmd, GpuVolume& volume, const SkyInput& sky);

  std::optional<gpu::SkyHeader> header() const { return header_; } // the file's sky section, if any
  std::size_t texels() const { return map_.size(); }

private:
  std::optional<gpu::SkyHeader> header_;
  glm::vec3 radiance_{0.0f};
  std::vector<glm::vec3> map_; // the current texels (the file's until a frame changes them)
};

} // namespace probebake::runtime::detail
