// The radiance of a ray that leaves the scene (docs/LIGHTING.md "The sky"): LightingInfo::sky_radiance times the
// sky map's bilinear lookup (sky_map.h, the bake's sky::EquirectMap::sample step for step), or sky_radiance
// alone when the file has no sky section (the lighting_info binding then ends in zero words: width 0). Include
// after volume_bindings.glsl.
#ifndef PROBEBAKE_SKY_GLSL
#define PROBEBAKE_SKY_GLSL

#include "probebake/sky_map.h"

vec3 probebake_sky_texel(uint texel) {
  const uint i = uint(SKY_HEADER_WORDS) + 3u * texel;
  return vec3(uintBitsToFloat(probebake_sky_words[i]), uintBitsToFloat(probebake_sky_words[i + 1u]),
              uintBitsToFloat(probebake_sky_words[i + 2u]));
}

vec3 probebake_sky_radiance(vec3 dir) {
  const uint width = probebake_sky_words[0];
  if (width == 0u) return probebake_lighting.sky_radiance;
  const SkyTaps taps = sky_taps(dir, width, probebake_sky_words[1]);
  vec3 sum = vec3(0.0);
  for (int k = 0; k < 4; ++k) sum += taps.weight[k] * probebake_sky_texel(taps.texel[k]);
  return probebake_lighting.sky_radiance * sum;
}

#endif // PROBEBAKE_SKY_GLSL
