// The equirectangular map's lookups (sky_map.h's layout and taps) and the constant and physical skies.
#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "probebake/formats/error.h"
#include "probebake/sky/sky.h"

namespace probebake::sky {

glm::vec3 EquirectMap::sample(glm::vec3 direction) const {
  const gpu::SkyTaps taps = gpu::sky_taps(direction, std::uint32_t(width), std::uint32_t(height));
  glm::vec3 sum(0.0f);
  for (int k = 0; k < 4; ++k) sum += taps.weight[k] * texels[taps.texel[k]];
  return sum;
}

glm::vec3 texel_direction(int width, int height, int i, int j) {
  const float phi = 2.0f * gpu::SKY_PI * (float(i) + 0.5f) / float(width) - gpu::SKY_PI;
  const float theta = gpu::SKY_PI * (float(j) + 0.5f) / float(height);
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

glm::vec3 direction_from_angles(float elevation_degrees, float azimuth_degrees) {
  const float e = glm::radians(elevation_degrees), a = glm::radians(azimuth_degrees);
  return {std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)};
}

bool Sky::emits() const {
  if (!(colour.x > 0.0f || colour.y > 0.0f || colour.z > 0.0f)) return false;
  if (map.empty()) return true;
  return std::any_of(map.texels.begin(), map.texels.end(), [&](glm::vec3 t) {
    const glm::vec3 l = colour * t;
    return l.x > 0.0f || l.y > 0.0f || l.z > 0.0f;
  });
}

Sky constant_sky(glm::vec3 radiance) {
  if (!(std::isfinite(radiance.x) && std::isfinite(radiance.y) && std::isfinite(radiance.z)) ||
      std::min({radiance.x, radiance.y, radiance.z}) < 0.0f)
    throw Error(ErrorKind::usage, "sky radiance (" + std::to_string(radiance.x) + ", " + std::to_string(radiance.y) +
                                      ", " + std::to_string(radiance.z) + ") must be finite and >= 0");
  return Sky{radiance, {}, 0, std::nullopt, {}};
}

Sky physical_sky(const PhysicalSky& physical) {
  const glm::vec3 d = physical.sun_direction;
  if (!(physical.turbidity >= kMinTurbidity && physical.turbidity <= kMaxTurbidity))
    throw Error(ErrorKind::usage, "turbidity " + std::to_string(physical.turbidity) + " must be in [1.7, 10]");
  if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) || !(glm::length(d) > 0.0f))
    throw Error(ErrorKind::usage, "the sun direction must be finite and not zero");
  PhysicalSky unit = physical;
  unit.sun_direction = glm::normalize(d);
  return Sky{glm::vec3(1.0f), physical_sky_map(unit), gpu::SKY_KIND_PHYSICAL, unit, {}};
}

EquirectMap physical_sky_map(const PhysicalSky& sky, int width, int height) {
  EquirectMap map{width, height, std::vector<glm::vec3>(std::size_t(width) * std::size_t(height))};
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      map.texels[std::size_t(j) * std::size_t(width) + std::size_t(i)] =
          physical_sky_radiance(sky, texel_direction(width, height, i, j));
  return map;
}

} // namespace probebake::sky
