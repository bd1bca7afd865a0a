#include "probebake/formats/sky_section.h"

#include <cstring>

namespace probebake::formats {

std::vector<std::uint32_t> sky_section_words(const gpu::SkyHeader& header, std::span<const glm::vec3> texels) {
  std::vector<std::uint32_t> words(std::size_t(gpu::SKY_HEADER_WORDS) + 3 * texels.size());
  std::memcpy(words.data(), &header, sizeof(header));
  for (std::size_t k = 0; k < texels.size(); ++k)
    std::memcpy(words.data() + gpu::SKY_HEADER_WORDS + 3 * k, &texels[k][0], 3 * sizeof(float));
  return words;
}

std::optional<SkyView> sky_view(std::span<const std::uint32_t> words) {
  if (words.size() < std::size_t(gpu::SKY_HEADER_WORDS)) return std::nullopt;
  SkyView view;
  std::memcpy(&view.header, words.data(), sizeof(view.header));
  const gpu::SkyHeader& h = view.header;
  if (h.width < 4 || h.width > gpu::SKY_MAX_WIDTH || h.height < 2 || h.height > gpu::SKY_MAX_HEIGHT)
    return std::nullopt;
  const std::size_t texels = std::size_t(h.width) * std::size_t(h.height);
  if (words.size() - std::size_t(gpu::SKY_HEADER_WORDS) != 3 * texels) return std::nullopt;
  view.texels.resize(texels);
  for (std::size_t k = 0; k < texels; ++k)
    std::memcpy(&view.texels[k][0], words.data() + gpu::SKY_HEADER_WORDS + 3 * k, 3 * sizeof(float));
  return view;
}

} // namespace probebake::formats
