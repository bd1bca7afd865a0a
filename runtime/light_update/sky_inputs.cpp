#include "light_update/sky_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/commands.h"
#include "light_update/light_inputs.h"
#include "probebake/formats/sky_section.h"

namespace probebake::runtime::detail {
SkyInputs::SkyInputs(glm::vec3 radiance, std::span<const std::uint32_t> sky_section) : radiance_(radiance) {
  if (std::optional<formats::SkyView> view = formats::sky_view(sky_section)) { // the upload validated it
    header_ = view->header;
    map_ = std::move(view->texels);
  }
}

Status SkyInputs::check(const SkyInput& sky) const {
  if (!finite_non_negative(sky.radiance))
    return {StatusCode::invalid_argument, "run_frame: sky radiance is not finite and >= 0"};
  if (!sky.map.empty() && sky.map.size() != map_.size())
    return {StatusCode::invalid_argument,
            "run_frame: a sky map of " + std::to_string(sky.map.size()) + " texels, but the file's has " +
                std::to_string(map_.size()) +
                (map_.empty() ? " (it has no sky section: give the radiance alone)" : "")};
  for (std::size_t k = 0; k < sky.map.size(); ++k)
    if (!finite_non_negative(sky.map[k]))
      return {StatusCode::invalid_argument,
              "run_frame: sky map texel " + std::to_string(k) + " is not finite and >= 0"};
  return {};
}

bool SkyInputs::record(VkCommandBuffer cmd, GpuVolume& volume, const SkyInput& sky) {
  const bool radiance_changed = std::memcmp(&sky.radiance, &radiance_, sizeof radiance_) != 0;
  const bool map_changed =
      !sky.map.empty() && std::memcmp(sky.map.data(), map_.data(), map_.size() * sizeof(glm::vec3)) != 0;
  if (!radiance_changed && !map_changed) return false;
  // Last frame's passes read the sky before it is overwritten.
  barrier(cmd, kAnyDeviceAccess, kTransferWrite);
  if (radiance_changed) {
    radiance_ = sky.radiance;
    vkCmdUpdateBuffer(cmd, volume.buffer(Section::lighting_info).get(), offsetof(gpu::LightingInfo, sky_radiance),
                      sizeof radiance_, &radiance_);
  }
  if (map_changed) {
    std::copy(sky.map.begin(), sky.map.end(), map_.begin());
    // The sky section rides in the lighting_info buffer after LightingInfo (gpu_volume.cpp).
    update_buffer(cmd, volume.buffer(Section::lighting_info).get(), sizeof(gpu::LightingInfo) + sizeof(gpu::SkyHeader),
                  map_.data(), map_.size() * sizeof(glm::vec3));
  }
  barrier(cmd, kTransferWrite, kAnyDeviceAccess);
  return true;
}

} // namespace probebake::runtime::detail
