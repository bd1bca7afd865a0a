// An equirectangular OpenEXR environment as the sky (sky.h environment_sky): checked, then averaged down.
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <fmt/core.h>

#include "probebake/formats/error.h"
#include "probebake/sky/sky.h"

namespace probebake::sky {
namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};
constexpr std::uintmax_t kMaxEnvironmentFileBytes = 2ull << 30;

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& place, const std::string& reason) {
  throw Error(ErrorKind::input, fmt::format("{}: {}: {}", path.string(), place, reason));
}

struct SourceImage {
  int width = 0, height = 0;
  std::vector<glm::vec3> pixels;
};

SourceImage read_rgb(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) refuse(path, "file", "cannot be read: " + ec.message());
  if (bytes > kMaxEnvironmentFileBytes) refuse(path, "file", fmt::format("{} bytes, more than 2 GiB", bytes));
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const long long w = (long long)window.max.x - window.min.x + 1, h = (long long)window.max.y - window.min.y + 1;
    if (w < 2 || h < 1 || w * h > kMaxEnvironmentTexels)
      refuse(path, "data window", fmt::format("{} x {} texels (at most {} in all)", w, h, kMaxEnvironmentTexels));
    if (w != 2 * h)
      refuse(path, "data window", fmt::format("{} x {}: an equirectangular map is twice as wide as high", w, h));
    for (const char* name : kChannels)
      if (file.header().channels().findChannel(name) == nullptr)
        refuse(path, "channels", fmt::format("no {} channel", name));
    SourceImage image{int(w), int(h), std::vector<glm::vec3>(std::size_t(w * h))};
    Imf::FrameBuffer frame;
    // The frame buffer is addressed in data-window coordinates: shift the base to pixel (min.x, min.y).
    const std::ptrdiff_t origin = std::ptrdiff_t(window.min.y) * std::ptrdiff_t(w) + window.min.x;
    for (int c = 0; c < 3; ++c) {
      char* base = reinterpret_cast<char*>(&image.pixels[0][c]) - origin * std::ptrdiff_t(sizeof(glm::vec3));
      frame.insert(kChannels[c], Imf::Slice(Imf::FLOAT, base, sizeof(glm::vec3), sizeof(glm::vec3) * std::size_t(w)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    refuse(path, "OpenEXR", e.what());
  }
}

void check_values(const std::filesystem::path& path, const SourceImage& image) {
  for (std::size_t k = 0; k < image.pixels.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const float v = image.pixels[k][c];
      if (!std::isfinite(v) || v < 0.0f)
        refuse(path,
               fmt::format("texel ({}, {}) channel {}", k % std::size_t(image.width), k / std::size_t(image.width),
                           kChannels[c]),
               fmt::format("{} (radiance must be finite and >= 0)", v));
    }
}

// Each source texel into the output texel holding its centre, weighted by its solid angle (sin theta), so that
// the map's integral over the sphere stays the source's.
EquirectMap average_down(const SourceImage& image) {
  const int width = std::min(image.width, kEnvironmentWidth), height = width / 2;
  EquirectMap map{width, height, std::vector<glm::vec3>(std::size_t(width) * std::size_t(height), glm::vec3(0.0f))};
  std::vector<double> weights(map.texels.size(), 0.0);
  std::vector<glm::dvec3> sums(map.texels.size(), glm::dvec3(0.0));
  for (int j = 0; j < image.height; ++j) {
    const double weight = std::sin(gpu::SKY_PI * (double(j) + 0.5) / double(image.height));
    const int row = int((std::int64_t(j) * height) / image.height);
    for (int i = 0; i < image.width; ++i) {
      const std::size_t out =
          std::size_t(row) * std::size_t(width) + std::size_t((std::int64_t(i) * width) / image.width);
      sums[out] += weight * glm::dvec3(image.pixels[std::size_t(j) * std::size_t(image.width) + std::size_t(i)]);
      weights[out] += weight;
    }
  }
  for (std::size_t k = 0; k < map.texels.size(); ++k) map.texels[k] = glm::vec3(sums[k] / weights[k]);
  return map;
}

} // namespace

Sky environment_sky(const std::filesystem::path& exr, float intensity) {
  if (!std::isfinite(intensity) || intensity < 0.0f)
    throw Error(ErrorKind::usage, fmt::format("sky intensity {} must be finite and >= 0", intensity));
  const SourceImage image = read_rgb(exr);
  check_values(exr, image);
  return Sky{glm::vec3(intensity), average_down(image), gpu::SKY_KIND_ENVIRONMENT, std::nullopt, exr};
}

} // namespace probebake::sky
