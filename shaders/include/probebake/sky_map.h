// The sky's radiance map (format 1.9, optional section `sky`): what rays that leave the scene see, shared by
// C++ (sky/sky.h, the bake) and GLSL (sky.glsl, the runtime's light update), so that both read the same
// texels with the same weights.
//
// uint32[SKY_HEADER_WORDS + 3 * width * height]: a SkyHeader, then RGB floats per texel, row-major, row 0 at
// the zenith (+Y, glTF's up). Texel (i, j) covers longitude phi in 2 pi [i, i + 1) / width - pi and polar
// angle theta in pi [j, j + 1) / height; a direction d has theta = acos(d.y), phi = atan(d.x, -d.z), so the
// map's middle column looks along -Z (glTF's forward) and its left quarter along -X. A lookup blends the four
// texel centres around d bilinearly (wrapping in phi, clamped at the poles). The radiance of a ray that
// leaves the scene is LightingInfo::sky_radiance times the map's value (docs/LIGHTING.md "The sky").
#ifndef PROBEBAKE_SKY_MAP_H
#define PROBEBAKE_SKY_MAP_H

#include "probebake/gpu_shared.h"

#ifdef __cplusplus
#include <cmath>
#include <cstddef>

#include <glm/vec3.hpp>
#endif

PB_GPU_BEGIN
#ifdef __cplusplus
using vec3 = glm::vec3;
inline float atan(float y, float x) { return std::atan2(y, x); } // GLSL's two-argument atan
using std::acos;
using std::floor;
using std::max;
using std::min;
#endif

PB_CONSTANT(int, SKY_HEADER_WORDS, 8);
PB_CONSTANT(uint, SKY_MAX_WIDTH, 1024u);
PB_CONSTANT(uint, SKY_MAX_HEIGHT, 512u);
PB_CONSTANT(uint, SKY_KIND_ENVIRONMENT, 1u); // an OpenEXR environment (probebake bake --sky FILE.exr)
PB_CONSTANT(uint, SKY_KIND_PHYSICAL, 2u);    // the analytic daylight sky of the sun's direction (sky/sky.h)
PB_CONSTANT(float, SKY_PI, 3.14159265f);

struct SkyHeader {
  uint width;         // offset  0: texels around, 4..SKY_MAX_WIDTH
  uint height;        // offset  4: texels from zenith to nadir, 2..SKY_MAX_HEIGHT
  uint kind;          // offset  8: SKY_KIND_*
  float turbidity;    // offset 12: the physical sky's turbidity (SKY_KIND_PHYSICAL), else 0
  vec3 sun_direction; // offset 16: unit, towards the sun (SKY_KIND_PHYSICAL), else 0
  int sun_light;      // offset 28: the sun's index in punctual_lights (SKY_KIND_PHYSICAL), else -1
};                    // size 32 = SKY_HEADER_WORDS words

// The four texels a lookup in direction `dir` (unit) blends and their weights (summing to 1).
struct SkyTaps {
  uint texel[4];
  float weight[4];
};

PB_FUNCTION SkyTaps sky_taps(vec3 dir, uint width, uint height) {
  const float u = atan(dir.x, -dir.z) / (2.0f * SKY_PI) + 0.5f;
  const float v = acos(max(-1.0f, min(1.0f, dir.y))) / SKY_PI;
  const float x = u * float(width) - 0.5f, y = v * float(height) - 0.5f;
  const float x0 = floor(x), y0 = floor(y);
  const float fx = x - x0, fy = y - y0;
  const int w = int(width), h = int(height);
  // x lies in [-0.5, width - 0.5]: only column -1 wraps (GLSL leaves % of negative numbers undefined).
  const int i0 = int(x0) < 0 ? w - 1 : min(w - 1, int(x0)), i1 = i0 + 1 == w ? 0 : i0 + 1;
  const int j0 = max(0, min(h - 1, int(y0))), j1 = max(0, min(h - 1, int(y0) + 1));
  SkyTaps taps;
  taps.texel[0] = uint(j0 * w + i0);
  taps.texel[1] = uint(j0 * w + i1);
  taps.texel[2] = uint(j1 * w + i0);
  taps.texel[3] = uint(j1 * w + i1);
  taps.weight[0] = (1.0f - fx) * (1.0f - fy);
  taps.weight[1] = fx * (1.0f - fy);
  taps.weight[2] = (1.0f - fx) * fy;
  taps.weight[3] = fx * fy;
  return taps;
}

#ifdef __cplusplus
static_assert(sizeof(SkyHeader) == 4 * SKY_HEADER_WORDS && offsetof(SkyHeader, sun_direction) == 16);
#endif
PB_GPU_END

#endif // PROBEBAKE_SKY_MAP_H
