// Preetham, Shirley and Smits, "A Practical Analytic Model for Daylight" (SIGGRAPH 1999): appendix A.2's
// Perez coefficients and zenith values, written from the paper; the sun's transmittance from its section 3.1
// (Angstrom's beta from turbidity) with a Rayleigh optical depth of 0.0973 at 550 nm scaled by lambda^-4 and
// Kasten and Young's (1989) relative air mass.
#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "probebake/sky/sky.h"

namespace probebake::sky {
namespace {

constexpr float kPi = gpu::SKY_PI;

struct Perez {
  float a, b, c, d, e;
  // F(theta, gamma), theta from the zenith, gamma from the sun.
  float operator()(float cos_theta, float gamma) const {
    const float cos_gamma = std::cos(gamma);
    return (1.0f + a * std::exp(b / std::max(cos_theta, 1e-4f))) *
           (1.0f + c * std::exp(d * gamma) + e * cos_gamma * cos_gamma);
  }
};

Perez luminance_coefficients(float t) {
  return {0.1787f * t - 1.4630f, -0.3554f * t + 0.4275f, -0.0227f * t + 5.3251f, 0.1206f * t - 2.5771f,
          -0.0670f * t + 0.3703f};
}
Perez x_coefficients(float t) {
  return {-0.0193f * t - 0.2592f, -0.0665f * t + 0.0008f, -0.0004f * t + 0.2125f, -0.0641f * t - 0.8989f,
          -0.0033f * t + 0.0452f};
}
Perez y_coefficients(float t) {
  return {-0.0167f * t - 0.2608f, -0.0950f * t + 0.0092f, -0.0079f * t + 0.2102f, -0.0441f * t - 1.6537f,
          -0.0109f * t + 0.0529f};
}

// Zenith luminance (kcd/m^2) and chromaticity for turbidity t and sun zenith angle s (radians).
glm::vec3 zenith_xyY(float t, float s) {
  const float chi = (4.0f / 9.0f - t / 120.0f) * (kPi - 2.0f * s);
  const float luminance = (4.0453f * t - 4.9710f) * std::tan(chi) - 0.2155f * t + 2.4192f;
  const float s2 = s * s, s3 = s2 * s, t2 = t * t;
  const float x = t2 * (0.00166f * s3 - 0.00375f * s2 + 0.00209f * s) +
                  t * (-0.02903f * s3 + 0.06377f * s2 - 0.03202f * s + 0.00394f) +
                  (0.11693f * s3 - 0.21196f * s2 + 0.06052f * s + 0.25886f);
  const float y = t2 * (0.00275f * s3 - 0.00610f * s2 + 0.00317f * s) +
                  t * (-0.04214f * s3 + 0.08970f * s2 - 0.04153f * s + 0.00516f) +
                  (0.15346f * s3 - 0.26756f * s2 + 0.06670f * s + 0.26688f);
  return {x, y, luminance};
}

// CIE xyY to linear sRGB (D65). Colours just outside the gamut lose their negative channels.
glm::vec3 xyY_to_rgb(float x, float y, float luminance) {
  if (!(y > 0.0f)) return glm::vec3(0.0f);
  const float X = x * luminance / y, Y = luminance, Z = (1.0f - x - y) * luminance / y;
  const glm::vec3 rgb(3.2406f * X - 1.5372f * Y - 0.4986f * Z, -0.9689f * X + 1.8758f * Y + 0.0415f * Z,
                      0.0557f * X - 0.2040f * Y + 1.0570f * Z);
  return glm::max(rgb, glm::vec3(0.0f));
}

// The sun's direction the model is evaluated at (on the horizon when below it) and the twilight fade.
struct SunForSky {
  glm::vec3 direction;
  float fade;
};
SunForSky sun_for_sky(glm::vec3 sun) {
  sun = glm::normalize(sun);
  if (sun.y >= 0.0f) return {sun, 1.0f};
  const float elevation_degrees = glm::degrees(std::asin(std::max(-1.0f, sun.y)));
  const glm::vec3 horizontal(sun.x, 0.0f, sun.z);
  const float length = glm::length(horizontal);
  return {length > 0.0f ? horizontal / length : glm::vec3(0.0f, 0.0f, -1.0f), std::exp(elevation_degrees / 2.0f)};
}

} // namespace

glm::vec3 physical_sky_radiance(const PhysicalSky& sky, glm::vec3 direction) {
  if (!(direction.y > 0.0f)) return glm::vec3(0.0f);
  const SunForSky sun = sun_for_sky(sky.sun_direction);
  const float t = sky.turbidity;
  const float sun_zenith = std::acos(std::min(1.0f, sun.direction.y));
  const float gamma = std::acos(std::clamp(glm::dot(direction, sun.direction), -1.0f, 1.0f));
  const glm::vec3 zenith = zenith_xyY(t, sun_zenith);
  const Perez fy = luminance_coefficients(t), fx = x_coefficients(t), fyc = y_coefficients(t);
  const float luminance = zenith.z * fy(direction.y, gamma) / fy(1.0f, sun_zenith);
  const float x = zenith.x * fx(direction.y, gamma) / fx(1.0f, sun_zenith);
  const float y = zenith.y * fyc(direction.y, gamma) / fyc(1.0f, sun_zenith);
  return sun.fade * xyY_to_rgb(x, y, std::max(0.0f, luminance));
}

glm::vec3 sun_irradiance(const PhysicalSky& sky) {
  const glm::vec3 sun = glm::normalize(sky.sun_direction);
  if (!(sun.y > 0.0f)) return glm::vec3(0.0f);
  const float zenith_degrees = glm::degrees(std::acos(std::min(1.0f, sun.y)));
  const float air_mass = 1.0f / (sun.y + 0.50572f * std::pow(96.07995f - zenith_degrees, -1.6364f));
  const float beta = 0.04608365822f * sky.turbidity - 0.04586025928f;
  const glm::vec3 lambda_um(0.680f, 0.550f, 0.440f);
  glm::vec3 transmittance;
  for (int c = 0; c < 3; ++c) {
    const float rayleigh = 0.0973f * std::pow(0.550f / lambda_um[c], 4.0f);
    const float aerosol = beta * std::pow(lambda_um[c], -1.3f);
    transmittance[c] = std::exp(-air_mass * (rayleigh + aerosol));
  }
  return 128.0f * transmittance;
}

} // namespace probebake::sky
