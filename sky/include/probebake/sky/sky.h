// The sky: the light of rays that leave the scene, a light like any other (docs/LIGHTING.md "The sky").
// A constant colour, an OpenEXR environment, or an analytic daylight sky driven by the sun's direction with the
// sun as a directional light. The bake, the path-traced reference and the runtime read the same radiance map
// (probebake/sky_map.h), so that they agree texel for texel; the runtime's host re-makes the physical sky's
// map when the sun moves (physical_sky_map) and the light update relights only the rays that left the scene.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/sky_map.h"

namespace probebake::sky {

// An equirectangular radiance map in sky_map.h's layout (row 0 at the zenith, RGB per texel).
struct EquirectMap {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> texels; // width * height, row-major

  bool empty() const { return texels.empty(); }
  glm::vec3 sample(glm::vec3 direction) const; // bilinear (gpu::sky_taps); `direction` unit
};

// The unit direction through the centre of texel (i, j) of a width x height map.
glm::vec3 texel_direction(int width, int height, int i, int j);
// The unit direction towards the sun at `elevation` degrees above the horizon and `azimuth` degrees from -Z
// (glTF's forward) towards +X, the map's own longitude.
glm::vec3 direction_from_angles(float elevation_degrees, float azimuth_degrees);

// The analytic daylight sky of Preetham, Shirley and Smits, "A Practical Analytic Model for Daylight"
// (SIGGRAPH 1999): the Perez distribution of luminance and chromaticity, fitted to turbidity and the sun's
// zenith angle, converted from xyY to linear sRGB. Radiance in kcd/m^2 (so that with the sun in klux the
// scene's lights keep their glTF scale: a sun of 100 klux is intensity 100). Below the horizon the sky is
// black (the ground beyond the scene is not lit: model it in the scene). With the sun below the horizon the
// sky of a sun on the horizon fades by exp(elevation / 2 degrees), a twilight stand-in, not a model of it.
struct PhysicalSky {
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f}; // unit, towards the sun
  float turbidity = 2.5f;                    // [kMinTurbidity, kMaxTurbidity]: 2 clear, 6 hazy
};
inline constexpr float kMinTurbidity = 1.7f, kMaxTurbidity = 10.0f; // Preetham's fit's range
inline constexpr int kPhysicalSkyWidth = 64, kPhysicalSkyHeight = 32;
glm::vec3 physical_sky_radiance(const PhysicalSky& sky, glm::vec3 direction);
EquirectMap physical_sky_map(const PhysicalSky& sky, int width = kPhysicalSkyWidth, int height = kPhysicalSkyHeight);
// The sun's irradiance at normal incidence (klux per channel): 128 klux outside the atmosphere times the
// transmittance of Rayleigh and aerosol extinction (Angstrom's law with Preetham's turbidity-to-beta fit)
// along Kasten and Young's relative air mass; 0 below the horizon. An approximation, not Preetham's spectral sun.
glm::vec3 sun_irradiance(const PhysicalSky& sky);

struct Sky {
  glm::vec3 colour{0.0f}; // constant radiance (W/(m^2 sr)) in every direction, or the map's scale per channel
  EquirectMap map;        // empty: `colour` everywhere
  std::uint32_t kind = 0; // gpu::SKY_KIND_* with a map
  std::optional<PhysicalSky> physical; // how the map was made (kind == SKY_KIND_PHYSICAL)
  std::filesystem::path source;        // the environment's file (an input no output may replace), else empty

  bool emits() const; // any direction has radiance > 0
  glm::vec3 radiance(glm::vec3 direction) const { return map.empty() ? colour : colour * map.sample(direction); }
};

// Throw Error(usage) naming the value when a radiance is not finite and >= 0, or a physical sky's turbidity is
// outside [kMinTurbidity, kMaxTurbidity] or its sun direction not finite and non-zero.
Sky constant_sky(glm::vec3 radiance);
Sky physical_sky(const PhysicalSky& physical);
// An equirectangular OpenEXR (R, G, B; A ignored) in sky_map.h's orientation, averaged down to at most
// kEnvironmentWidth x kEnvironmentHeight texels (a 2:1 map; others are refused), times `intensity`.
// Hostile input: the data window is checked before any allocation (at most kMaxEnvironmentTexels), every value
// must be finite and >= 0. Throws Error(input) "<file>: <place>: <reason>".
inline constexpr int kEnvironmentWidth = 128, kEnvironmentHeight = 64;
inline constexpr long long kMaxEnvironmentTexels = 64ll << 20;
Sky environment_sky(const std::filesystem::path& exr, float intensity = 1.0f);

} // namespace probebake::sky
