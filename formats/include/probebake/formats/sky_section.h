// The sky section (format 1.9, optional; probebake/sky_map.h SkyHeader and texels): the radiance map of the rays
// that leave the scene, present when the bake had a sky other than a constant colour, and the rules a file's sky
// must keep (validate.h "sky").
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/probe_volume.h"
#include "probebake/sky_map.h"

namespace probebake::formats {

// The section's words: the header, then RGB floats per texel (width * height of them).
std::vector<std::uint32_t> sky_section_words(const gpu::SkyHeader& header, std::span<const glm::vec3> texels);

// A section as read: its header and texels, or nothing when the section is absent or its size is not a header
// of sizes in range and its texels (validate reports why).
struct SkyView {
  gpu::SkyHeader header{};
  std::vector<glm::vec3> texels;
};
std::optional<SkyView> sky_view(std::span<const std::uint32_t> words);

} // namespace probebake::formats
