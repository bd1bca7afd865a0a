#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <fmt/core.h>
#include <stb_image_write.h>

#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"
#include "probebake/render/render.h"

namespace probebake::render {
namespace {

std::uint8_t srgb_byte(float linear) {
  const float v = std::clamp(linear, 0.0f, 1.0f);
  const float srgb = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return std::isfinite(srgb) ? static_cast<std::uint8_t>(std::lround(255.0f * srgb)) : 0;
}

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  out->insert(out->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
}

} // namespace

float exposure_of(const bake::Image& image) {
  std::vector<float> luminance;
  luminance.reserve(image.pixels.size());
  for (const glm::vec3& p : image.pixels) luminance.push_back(0.2126f * p.x + 0.7152f * p.y + 0.0722f * p.z);
  if (luminance.empty()) return 1.0f;
  const auto at = luminance.begin() + std::ptrdiff_t(luminance.size() * 99 / 100);
  std::nth_element(luminance.begin(), at, luminance.end());
  return *at > 0.0f && std::isfinite(*at) ? 1.0f / *at : 1.0f;
}

void write_image(const std::filesystem::path& path, const bake::Image& image, float exposure) {
  const std::string extension = path.extension().string();
  if (extension == ".exr") return bake::write_exr(path, image);
  if (extension != ".png")
    throw Error(ErrorKind::usage, fmt::format("{}: images are written as .png or .exr", path.string()));
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
    throw Error(ErrorKind::internal, fmt::format("{}: image size does not match its pixels", path.string()));
  std::vector<std::uint8_t> rgb;
  rgb.reserve(image.pixels.size() * 3);
  for (const glm::vec3& p : image.pixels)
    for (int c = 0; c < 3; ++c) rgb.push_back(srgb_byte(p[c] * exposure));
  std::vector<std::uint8_t> png;
  if (stbi_write_png_to_func(append_bytes, &png, image.width, image.height, 3, rgb.data(), image.width * 3) == 0)
    throw Error(ErrorKind::output, fmt::format("{}: cannot encode PNG", path.string()));
  write_file_atomically(path, png);
}

} // namespace probebake::render
